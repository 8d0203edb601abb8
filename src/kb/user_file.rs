//! A user's knowledge-base file as the engine reads it. scryer-prolog
//! 0.10 reads a comment after a file's last clause (`% last line`) as a
//! syntax error (incomplete_reduction) instead of the end of the file; the
//! engine reads a copy that ends in `end_of_file.` on a line of its own,
//! its lines numbered as in the file, without the byte-order mark an
//! editor may have put first (which the engine reads as a syntax error).

/// A copy of a user's file with `end_of_file.` on a line after its text,
/// in the temporary folder; removed when dropped.
pub(super) struct ConsultCopy {
    /// Where the copy is.
    pub(super) path: std::path::PathBuf,
    /// The lines of the file itself.
    pub(super) lines: u64,
}

impl ConsultCopy {
    /// None where the file cannot be read or the copy written (the file
    /// is then read as it is).
    pub(super) fn of(path: &std::path::Path) -> Option<ConsultCopy> {
        static COPIES: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
        let text = std::fs::read_to_string(path).ok()?;
        // nor does it read a byte-order mark (editors on Windows write one)
        let mut text = text.strip_prefix('\u{feff}').unwrap_or(&text).to_string();
        let lines = text.lines().count() as u64;
        text.push_str("\nend_of_file.\n");
        let n = COPIES.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
        let copy = std::env::temp_dir().join(format!("freemesh-kb-{}-{n}.pl", std::process::id()));
        std::fs::write(&copy, text).ok()?;
        Some(ConsultCopy { path: copy, lines })
    }
}

impl Drop for ConsultCopy {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.path);
    }
}
