//! The files a `mesh` run writes: each domain's outputs named from the
//! `-o` and `--trace` patterns, all of them checked before anything is
//! meshed (no file named twice, every folder there and writable), so that
//! a mistake costs no meshing time and leaves nothing written.

use anyhow::{bail, Result};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

use freemesh::{check_writable, Format};

/// What one domain's run writes.
#[derive(Debug, Clone)]
pub struct DomainOutputs {
    /// The mesh files, each in the format of its extension.
    pub meshes: Vec<(PathBuf, Format)>,
    /// The inference trace, if asked for.
    pub trace: Option<PathBuf>,
}

impl DomainOutputs {
    fn paths(&self) -> impl Iterator<Item = &Path> {
        self.meshes
            .iter()
            .map(|(p, _)| p.as_path())
            .chain(self.trace.as_deref())
    }
}

/// The outputs of every domain, in the order of `domains`, checked:
/// `{stem}` in a pattern is the domain's file name without its extension
/// (needed when there are several domains), no two outputs are the same
/// file, and each can be written.
pub fn plan(
    domains: &[PathBuf],
    patterns: &[PathBuf],
    trace: Option<&Path>,
) -> Result<Vec<DomainOutputs>> {
    let formats: Vec<Format> = patterns
        .iter()
        .map(|p| Format::from_path(p))
        .collect::<Result<_, _>>()?;
    if domains.len() > 1 {
        for p in patterns.iter().map(PathBuf::as_path).chain(trace) {
            if !p.to_string_lossy().contains("{stem}") {
                bail!(
                    "{} domains and one output name {}: write {{stem}} where each domain's name goes (-o 'out/{{stem}}.msh')",
                    domains.len(),
                    p.display()
                );
            }
        }
    }
    let planned: Vec<DomainOutputs> = domains
        .iter()
        .enumerate()
        .map(|(i, d)| {
            let stem = d
                .file_stem()
                .map_or_else(|| format!("{i}"), |s| s.to_string_lossy().into_owned());
            let fill = |p: &Path| PathBuf::from(p.to_string_lossy().replace("{stem}", &stem));
            DomainOutputs {
                meshes: patterns
                    .iter()
                    .map(|p| fill(p))
                    .zip(formats.iter().copied())
                    .collect(),
                trace: trace.map(fill),
            }
        })
        .collect();
    // which domain writes each file, by the file's place on disk
    let mut writer: HashMap<PathBuf, (usize, &Path)> = HashMap::new();
    for (i, outputs) in planned.iter().enumerate() {
        for p in outputs.paths() {
            check_writable(p)?;
            if let Some((j, earlier)) = writer.insert(place_on_disk(p), (i, p)) {
                if i == j {
                    bail!(
                        "{} is given twice as an output (one file cannot hold both)",
                        p.display()
                    );
                }
                bail!(
                    "{} and {} would both write {}: name the outputs apart",
                    domains[j].display(),
                    domains[i].display(),
                    earlier.display()
                );
            }
        }
    }
    Ok(planned)
}

/// The file a path names, its folder resolved (`out/a.msh` and
/// `./out/../out/a.msh` are one file); the folder is known to exist.
fn place_on_disk(path: &Path) -> PathBuf {
    let folder = match path.parent() {
        Some(f) if !f.as_os_str().is_empty() => f,
        _ => Path::new("."),
    };
    let name = path.file_name().unwrap_or_default();
    std::fs::canonicalize(folder)
        .unwrap_or_else(|_| folder.to_path_buf())
        .join(name)
}

/// Makes Ctrl-C (and a termination request) remove the temporaries of
/// the outputs being written and end the run with exit code 130, as a
/// shell reports an interrupted command.
pub fn remove_temporaries_on_interrupt() -> Result<()> {
    ctrlc::set_handler(|| {
        freemesh::interrupt_writes();
        std::process::exit(130);
    })?;
    // the handler above runs on a thread of its own, which a run about to
    // put its outputs in place can outrun: a flag set in the signal
    // handler itself stops the renames, and the exit code says so
    // (signal-hook calls the handler installed before its own)
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    for signal in [SIGINT, SIGTERM, SIGHUP] {
        signal_hook::flag::register(signal, freemesh::interrupted_flag())?;
    }
    Ok(())
}
