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
    /// The copy of the file at `path`; None where it cannot be written
    /// (the file is then read as it is); an error, in words, where the
    /// file is not UTF-8 text (the engine would read it as a syntax error
    /// on line 0).
    pub(super) fn of(path: &std::path::Path) -> Result<Option<ConsultCopy>, String> {
        static COPIES: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
        let bytes = std::fs::read(path).map_err(|e| e.to_string())?;
        let text = String::from_utf8(bytes).map_err(|e| {
            let at = e.utf8_error().valid_up_to();
            let line = 1 + e.as_bytes()[..at].iter().filter(|&&b| b == b'\n').count();
            format!("not UTF-8 text (line {line}; save the file as UTF-8)")
        })?;
        // nor does it read a byte-order mark (editors on Windows write one)
        let mut text = text.strip_prefix('\u{feff}').unwrap_or(&text).to_string();
        let lines = text.lines().count() as u64;
        text.push_str("\nend_of_file.\n");
        let n = COPIES.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
        let copy = std::env::temp_dir().join(format!("freemesh-kb-{}-{n}.pl", std::process::id()));
        Ok(std::fs::write(&copy, text)
            .ok()
            .map(|()| ConsultCopy { path: copy, lines }))
    }
}

impl Drop for ConsultCopy {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.path);
    }
}
