//! Writing results as transactions. Every output directory carries a manifest, `pcsim.json` (its
//! kind, the version, the command's overrides, the list of its files and `"complete": true`),
//! written last; readers (`pcsim plot`, `merge`) trust a directory only through a complete
//! manifest, and only the files it lists.
//!
//! A command writes into a staging directory beside `--out` (`.NAME.partial-PID`) under a lock
//! (`.NAME.pcsim-lock`, holding the writer's pid) and, when every file is written, swaps it into
//! place ([`OutDir::commit`]): a reused directory is **replaced whole** (the previous run's
//! figures and `cases/` files do not survive), and a second writer to the same directory is
//! refused while the first holds the lock. A run that fails, is interrupted or is killed leaves
//! the previous complete output as it was (and at most a hidden `.partial-PID` folder, which the
//! next writer removes); killed inside the swap itself, it may leave the previous output moved
//! aside as `.NAME.previous-PID`, which the next writer puts back (or removes, when the new
//! output was already in place). A directory that holds files pcsim did not write is refused, never
//! replaced.

use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};

pub use pcsim_core::study::manifest::{ManifestRecord, StudyManifest};

/// The manifest of an output directory.
pub const MANIFEST: &str = "pcsim.json";

/// Write `bytes` to `path`, naming the file in any error (a full disk, a file-size limit).
pub fn write_file(path: &Path, bytes: impl AsRef<[u8]>) -> Result<()> {
    std::fs::write(path, bytes).with_context(|| format!("cannot write {}", path.display()))
}

/// Write `bytes` to `path` through a temporary file and a rename: a reader sees the old file or
/// the new one, never a truncated one.
pub fn write_file_atomic(path: &Path, bytes: impl AsRef<[u8]>) -> Result<()> {
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    let tmp = path.with_file_name(format!(".{name}.tmp-{}", std::process::id()));
    if let Err(e) = write_file(&tmp, bytes) {
        // A full disk or a file-size limit: no temporary file is left behind.
        let _ = std::fs::remove_file(&tmp);
        return Err(e);
    }
    std::fs::rename(&tmp, path).with_context(|| {
        let _ = std::fs::remove_file(&tmp);
        format!("cannot move {} into place", path.display())
    })
}

/// Write the manifest of a directory being written: its `kind`, the pcsim version, the command
/// line, `complete: false`, and what the study adds. [`OutDir::commit`] completes it.
pub fn write_manifest(dir: &Path, kind: &str, study: StudyManifest) -> Result<()> {
    let m = ManifestRecord {
        kind: kind.to_string(),
        pcsim_version: env!("CARGO_PKG_VERSION").to_string(),
        complete: false,
        command: std::env::args().collect::<Vec<_>>().join(" "),
        files: None,
        hashes: None,
        study,
    };
    write_file(&dir.join(MANIFEST), manifest_text(&m)?)
}

/// A manifest as written: pretty JSON, its keys sorted.
fn manifest_text(m: &ManifestRecord) -> Result<String> {
    Ok(serde_json::to_string_pretty(&serde_json::to_value(m)?)? + "\n")
}

/// The largest manifest read, bytes (a manifest lists a sweep's files: a few hundred kB at most).
pub const MAX_MANIFEST_BYTES: u64 = 16 << 20;

/// Read the manifest of a directory as it is, complete or not (`None` when it has none).
pub fn read_manifest(dir: &Path) -> Result<Option<ManifestRecord>> {
    let path = dir.join(MANIFEST);
    if !path.exists() {
        return Ok(None);
    }
    let text = crate::common::read_text_limited(&path, MAX_MANIFEST_BYTES, "a manifest")?;
    let v: serde_json::Value = serde_json::from_str(&text)
        .with_context(|| format!("{} is not valid JSON", path.display()))?;
    ManifestRecord::from_value(v)
        .map(Some)
        .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))
}

/// The manifest of a complete output directory: its kind, its files and the whole record.
#[derive(Debug, Clone)]
pub struct Manifest {
    /// The kind of output: the study that wrote it.
    pub kind: pcsim_core::study::StudyKind,
    /// The pcsim version that wrote it.
    pub version: String,
    /// The files of the directory, relative to it (the manifest excluded).
    pub files: Vec<String>,
    /// The whole manifest.
    pub record: ManifestRecord,
}

/// Read the manifest of a complete output directory, refusing a directory without one, an
/// incomplete one (a run that was interrupted, or is still being written), or one whose listed
/// files are missing.
pub fn read_complete_manifest(dir: &Path) -> Result<Manifest> {
    let m = read_manifest(dir)?.with_context(|| {
        format!(
            "{} is not a complete output of pcsim (no {MANIFEST}: not written by pcsim, made by an older version, or interrupted)",
            dir.display()
        )
    })?;
    if !m.complete {
        bail!(
            "{} is not complete ({MANIFEST} does not say \"complete\": true): its run was interrupted, failed, or is still being written",
            dir.display()
        );
    }
    if m.kind.is_empty() {
        bail!("{}: {MANIFEST} has no `kind`", dir.display());
    }
    let kind = pcsim_core::study::StudyKind::parse(&m.kind)
        .with_context(|| format!("{}: {MANIFEST}", dir.display()))?;
    let version = m.pcsim_version.clone();
    let files: Vec<String> = m
        .files
        .clone()
        .with_context(|| format!("{}: {MANIFEST} has no list of `files`", dir.display()))?;
    // Figures are derived from the data files and may be redrawn (`pcsim plot`); every other
    // listed file must be there.
    for f in files.iter().filter(|f| !is_figure(f)) {
        if !dir.join(f).is_file() {
            bail!(
                "{}: {MANIFEST} lists {f}, which is missing (the directory was changed after pcsim wrote it)",
                dir.display()
            );
        }
    }
    Ok(Manifest {
        kind,
        version,
        files,
        record: m,
    })
}

/// A file drawn from the data files: a figure, the report or the assessment (`pcsim plot`,
/// `pcsim report` and `pcsim assess` write them again).
fn is_figure(f: &str) -> bool {
    f.ends_with(".svg")
        || f.ends_with(".png")
        || matches!(f, "report.html" | "assessment.csv" | "assessment.json")
}

impl Manifest {
    /// Whether the manifest lists `file` (relative to the directory).
    pub fn lists(&self, file: &str) -> bool {
        self.files.iter().any(|f| f == file)
    }
}

/// Every file under `dir`, relative to it and sorted, the manifest excluded.
fn files_under(dir: &Path) -> Result<Vec<String>> {
    fn walk(root: &Path, d: &Path, out: &mut Vec<String>) -> Result<()> {
        for e in std::fs::read_dir(d).with_context(|| format!("cannot read {}", d.display()))? {
            let p = e?.path();
            if p.is_dir() {
                walk(root, &p, out)?;
            } else {
                let rel = p.strip_prefix(root).unwrap_or(&p);
                out.push(rel.to_string_lossy().replace('\\', "/"));
            }
        }
        Ok(())
    }
    let mut out = Vec::new();
    walk(dir, dir, &mut out)?;
    out.retain(|f| f != MANIFEST);
    out.sort();
    Ok(out)
}

/// The FNV-1a 64-bit hash of a file's bytes (read in chunks), as 16 hexadecimal digits: what the
/// manifest records of each file, so that a file changed after pcsim wrote it is detected
/// ([`edited_files`]). Not cryptographic: it detects an edit, not an attack (the report never
/// trusts a figure's content anyway: it is sanitised).
pub fn file_hash(path: &Path) -> Result<String> {
    use std::io::Read;
    let mut f =
        std::fs::File::open(path).with_context(|| format!("cannot read {}", path.display()))?;
    let mut h = pcsim_core::fingerprint::FNV1A64_START;
    let mut buf = vec![0u8; 1 << 16];
    loop {
        let n = f
            .read(&mut buf)
            .with_context(|| format!("cannot read {}", path.display()))?;
        if n == 0 {
            break;
        }
        h = pcsim_core::fingerprint::fnv1a64_continue(h, &buf[..n]);
    }
    Ok(format!("{h:016x}"))
}

/// The files of a complete directory whose bytes are no longer those the manifest recorded
/// (edited, replaced or truncated after pcsim wrote them), or are missing; files written before
/// the manifest recorded hashes are not judged.
pub fn edited_files(dir: &Path, m: &Manifest) -> Vec<String> {
    let Some(h) = &m.record.hashes else {
        return Vec::new();
    };
    let mut out: Vec<String> = h
        .iter()
        .filter(|(f, want)| {
            *f != "report.html" && file_hash(&dir.join(f)).ok().as_deref() != Some(want.as_str())
        })
        .map(|(f, _)| f.clone())
        .collect();
    out.sort();
    out
}

/// Mark the manifest of `dir` complete, listing every file now in it with its hash (written
/// through a rename: the manifest is the last file to change).
pub fn complete_manifest(dir: &Path) -> Result<()> {
    let mut m = read_manifest(dir)?
        .with_context(|| format!("{}: no {MANIFEST} to complete", dir.display()))?;
    let files = files_under(dir)?;
    let mut hashes = std::collections::BTreeMap::new();
    for f in &files {
        hashes.insert(f.clone(), file_hash(&dir.join(f))?);
    }
    m.files = Some(files);
    m.hashes = Some(hashes);
    m.complete = true;
    write_file_atomic(&dir.join(MANIFEST), manifest_text(&m)?)
}

/// Add `figures` (paths under `dir`) to the file list of the complete manifest of `dir` (after
/// `pcsim plot` redrew them), leaving every other file as the manifest had it: a file someone
/// put into the directory by hand is never adopted as pcsim's.
pub fn add_to_manifest(dir: &Path, figures: &[PathBuf]) -> Result<()> {
    let m = read_complete_manifest(dir)?;
    let mut files = m.files;
    let mut record = m.record;
    for f in figures {
        let rel = f.strip_prefix(dir).unwrap_or(f);
        let rel = rel.to_string_lossy().replace('\\', "/");
        if let Some(h) = record.hashes.as_mut() {
            h.insert(rel.clone(), file_hash(&dir.join(&rel))?);
        }
        if !files.contains(&rel) {
            files.push(rel);
        }
    }
    files.sort();
    record.files = Some(files);
    write_file_atomic(&dir.join(MANIFEST), manifest_text(&record)?)
}

/// The lock of an output directory: a file beside it holding the writer's pid, made with
/// `create_new` (one writer at a time); a lock whose process has died is taken over.
#[derive(Debug)]
pub struct Lock {
    path: PathBuf,
}

fn pid_alive(pid: u32) -> bool {
    pid == std::process::id() || Path::new(&format!("/proc/{pid}")).exists()
}

/// A writer killed inside [`OutDir::commit`] leaves its `.NAME.previous-PID` folder (the
/// previous complete output, moved aside): killed before its new output was moved in, the target
/// is missing and the previous output is put back; killed after, the previous output is stale
/// and removed. Called under the lock, for writers that are no longer alive.
fn recover_killed_commit(target: &Path) {
    let name = target.file_name().unwrap_or_default().to_string_lossy();
    let prefix = format!(".{name}.previous-");
    let Ok(rd) = std::fs::read_dir(
        target
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new(".")),
    ) else {
        return;
    };
    for e in rd.flatten() {
        let n = e.file_name().to_string_lossy().to_string();
        let Some(pid) = n.strip_prefix(&prefix).and_then(|p| p.parse::<u32>().ok()) else {
            continue;
        };
        if pid_alive(pid) && pid != std::process::id() {
            continue;
        }
        if !target.exists() && std::fs::rename(e.path(), target).is_ok() {
            continue;
        }
        let _ = std::fs::remove_dir_all(e.path());
    }
}

fn sibling(target: &Path, suffix: &str) -> PathBuf {
    let name = target.file_name().unwrap_or_default().to_string_lossy();
    target.with_file_name(format!(".{name}.{suffix}"))
}

impl Lock {
    /// Take the lock of `target`, or refuse naming the writer that holds it.
    pub fn take(target: &Path) -> Result<Lock> {
        let path = sibling(target, "pcsim-lock");
        for _ in 0..2 {
            match std::fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&path)
            {
                Ok(mut f) => {
                    use std::io::Write;
                    let _ = writeln!(f, "{}", std::process::id());
                    return Ok(Lock { path });
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                    let holder = std::fs::read_to_string(&path)
                        .ok()
                        .and_then(|s| s.trim().parse::<u32>().ok());
                    match holder {
                        Some(pid) if pid_alive(pid) => bail!(
                            "{} is being written by another pcsim (pid {pid}, lock {}): wait for it, or choose another --out",
                            target.display(),
                            path.display()
                        ),
                        // A stale lock (its writer died, or it is being written this instant):
                        // take it over once.
                        _ => {
                            let _ = std::fs::remove_file(&path);
                        }
                    }
                }
                Err(e) => {
                    return Err(e)
                        .with_context(|| format!("cannot create the lock {}", path.display()))
                }
            }
        }
        bail!(
            "cannot take the lock {} of {}",
            path.display(),
            target.display()
        )
    }
}

impl Drop for Lock {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.path);
    }
}

/// Refuse to replace `target` unless it is absent, empty, or a pcsim output whose manifest lists
/// every file in it (files pcsim did not write are never deleted).
fn check_replaceable(target: &Path) -> Result<()> {
    if !target.exists() {
        return Ok(());
    }
    if !target.is_dir() {
        bail!(
            "--out {} exists and is not a directory: choose another --out",
            target.display()
        );
    }
    let present = files_under(target)?;
    let manifest = read_manifest(target).ok().flatten();
    if present.is_empty() && manifest.is_none() {
        return Ok(());
    }
    let m = manifest.with_context(|| {
        format!(
            "--out {} exists and is not an output of pcsim (no {MANIFEST}): choose another directory, or empty it",
            target.display()
        )
    })?;
    if let Some(listed) = &m.files {
        let foreign: Vec<&String> = present.iter().filter(|f| !listed.contains(f)).collect();
        if !foreign.is_empty() {
            bail!(
                "--out {} holds files that pcsim did not write ({}): they would be deleted when the new output replaces it; move them, or choose another --out",
                target.display(),
                foreign
                    .iter()
                    .take(5)
                    .map(|s| s.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            );
        }
    }
    Ok(())
}

/// An output directory written as a transaction (see the module's documentation): write into
/// [`OutDir::path`], then [`OutDir::commit`]. Dropped without a commit, it removes its staging
/// directory and leaves the target as it was.
#[derive(Debug)]
pub struct OutDir {
    target: PathBuf,
    staging: PathBuf,
    committed: bool,
    _lock: Lock,
}

impl OutDir {
    /// Lock `target`, check that it may be replaced, and make a fresh staging directory beside it.
    /// A `target` that is a symbolic link is followed: the output replaces the directory it
    /// points to (the link itself stays).
    pub fn begin(target: &Path) -> Result<OutDir> {
        let resolved;
        let target = match std::fs::symlink_metadata(target) {
            Ok(md) if md.file_type().is_symlink() => {
                resolved = std::fs::canonicalize(target).with_context(|| {
                    format!(
                        "--out {} is a symbolic link to nothing (its target is missing): create its target directory, or choose another --out",
                        target.display()
                    )
                })?;
                resolved.as_path()
            }
            _ => target,
        };
        if target.as_os_str().is_empty() || target.file_name().is_none() {
            bail!(
                "--out `{}`: name a directory (not `.`, `..` or a root)",
                target.display()
            );
        }
        if let Some(parent) = target.parent().filter(|p| !p.as_os_str().is_empty()) {
            std::fs::create_dir_all(parent)
                .with_context(|| format!("cannot create {}", parent.display()))?;
        }
        let lock = Lock::take(target)?;
        recover_killed_commit(target);
        check_replaceable(target)?;
        // Staging directories left by killed writers of this target.
        let name = target.file_name().unwrap_or_default().to_string_lossy();
        let prefix = format!(".{name}.partial-");
        if let Ok(rd) = std::fs::read_dir(
            target
                .parent()
                .filter(|p| !p.as_os_str().is_empty())
                .unwrap_or(Path::new(".")),
        ) {
            for e in rd.flatten() {
                let n = e.file_name().to_string_lossy().to_string();
                if let Some(pid) = n.strip_prefix(&prefix).and_then(|p| p.parse::<u32>().ok()) {
                    if !pid_alive(pid) || pid == std::process::id() {
                        let _ = std::fs::remove_dir_all(e.path());
                    }
                }
            }
        }
        let staging = sibling(target, &format!("partial-{}", std::process::id()));
        std::fs::create_dir_all(&staging)
            .with_context(|| format!("cannot create {}", staging.display()))?;
        Ok(OutDir {
            target: target.to_path_buf(),
            staging,
            committed: false,
            _lock: lock,
        })
    }

    /// Where the command writes its files (the staging directory).
    pub fn path(&self) -> &Path {
        &self.staging
    }

    /// Where files written into [`OutDir::path`] will be once committed (for messages).
    pub fn in_target(&self, files: &[PathBuf]) -> Vec<PathBuf> {
        files
            .iter()
            .map(|f| match f.strip_prefix(&self.staging) {
                Ok(rel) => self.target.join(rel),
                Err(_) => f.clone(),
            })
            .collect()
    }

    /// Complete the manifest (written by the command with [`write_manifest`]) and swap the
    /// staging directory into place: the previous output is removed only once the new one is
    /// whole.
    pub fn commit(mut self) -> Result<()> {
        complete_manifest(&self.staging)?;
        let previous = sibling(&self.target, &format!("previous-{}", std::process::id()));
        let had = self.target.exists();
        if had {
            std::fs::rename(&self.target, &previous).with_context(|| {
                format!(
                    "cannot move the previous output {} aside",
                    self.target.display()
                )
            })?;
        }
        if let Err(e) = std::fs::rename(&self.staging, &self.target) {
            if had {
                let _ = std::fs::rename(&previous, &self.target);
            }
            return Err(e).with_context(|| {
                format!("cannot move the new output into {}", self.target.display())
            });
        }
        self.committed = true;
        if had {
            std::fs::remove_dir_all(&previous).with_context(|| {
                format!("cannot remove the previous output {}", previous.display())
            })?;
        }
        Ok(())
    }
}

impl Drop for OutDir {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.staging);
        }
    }
}
