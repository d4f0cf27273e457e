//! Output files that never destroy an input: an output that is (after symbolic links, `..`
//! and hard links) one of the run's inputs, or another output, is refused before anything
//! is opened for writing ([`check_outputs`]); an output is written to a temporary file
//! beside its target and renamed over it only when complete ([`OutputFile`]), so that a
//! failed run leaves no partial output and the old file as it was.

use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Component, Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use super::error::CaptureError;

/// A file of a run with the name the user gave it for messages: `("--output", path)`,
/// `("capture", path)`.
pub type NamedPath<'a> = (&'a str, &'a Path);

/// The absolute path of `path` with its symbolic links and `..` resolved: its longest
/// existing ancestor's real path, then the rest of its components, each `..` taking one
/// back. That is the file the path names once the run has created the directories it
/// lacks (`new/../capture.csv` is the capture).
fn resolved(path: &Path) -> PathBuf {
    let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    let components: Vec<Component<'_>> = absolute.components().collect();
    for existing in (1..=components.len()).rev() {
        let Ok(mut real) = components[..existing]
            .iter()
            .collect::<PathBuf>()
            .canonicalize()
        else {
            continue;
        };
        for component in &components[existing..] {
            match component {
                Component::ParentDir => {
                    real.pop();
                }
                Component::CurDir => {}
                other => real.push(other),
            }
        }
        // The components left may lead back into existing files and links.
        return real.canonicalize().unwrap_or(real);
    }
    absolute
}

/// Whether `a` and `b` are one file: one device and inode (hard links, symbolic links and
/// any spelling of the path) where both exist, else one resolved path.
fn same_file(a: &Path, b: &Path) -> bool {
    let (a, b) = (resolved(a), resolved(b));
    #[cfg(unix)]
    if let (Ok(ma), Ok(mb)) = (std::fs::metadata(&a), std::fs::metadata(&b)) {
        use std::os::unix::fs::MetadataExt;
        return ma.dev() == mb.dev() && ma.ino() == mb.ino();
    }
    a == b
}

/// Refuses, before anything is written, an output that is one of the `inputs` or another
/// output; the error names both as the user named them.
///
/// ```
/// use angletrack::capture::check_outputs;
/// let dir = std::env::temp_dir().join(format!("angletrack_doc_outputs_{}", std::process::id()));
/// std::fs::create_dir_all(dir.join("out")).unwrap();
/// let capture = dir.join("capture.csv");
/// std::fs::write(&capture, "y_c,y_s\n1,0\n").unwrap();
/// let sneaky = dir.join("out").join("..").join("capture.csv");
/// let e = check_outputs(&[("--output", &sneaky)], &[("capture", &capture)]).unwrap_err();
/// assert!(e.to_string().contains("--output: is the capture"));
/// assert!(check_outputs(&[("--output", &dir.join("est.csv"))], &[("capture", &capture)]).is_ok());
/// # std::fs::remove_dir_all(&dir).unwrap();
/// ```
pub fn check_outputs(
    outputs: &[NamedPath<'_>],
    inputs: &[NamedPath<'_>],
) -> Result<(), CaptureError> {
    for (k, &(name, output)) in outputs.iter().enumerate() {
        let earlier = outputs[..k].iter().map(|&(n, p)| (n, p, "output"));
        let clash = inputs
            .iter()
            .map(|&(n, p)| (n, p, "input"))
            .chain(earlier)
            .find(|&(_, other, _)| same_file(output, other));
        if let Some((other_name, other, kind)) = clash {
            return Err(CaptureError::new(
                output,
                format!(
                    "{name}: is the {other_name} ({}, the same file): an output never replaces \
                     an {kind}; choose another name",
                    other.display()
                ),
            ));
        }
    }
    Ok(())
}

/// Makes the temporary files' names unique within the process.
static TEMPORARIES: AtomicU64 = AtomicU64::new(0);

/// A new temporary file beside `target` (same directory, so that the rename is atomic),
/// named `.NAME.PID-N.tmp`.
pub(crate) fn temporary_beside(target: &Path) -> Result<(PathBuf, File), CaptureError> {
    let name = target
        .file_name()
        .ok_or_else(|| CaptureError::new(target, "is not a file name (a directory or `..`)"))?;
    let dir = target.parent().unwrap_or(Path::new(""));
    loop {
        let n = TEMPORARIES.fetch_add(1, Ordering::Relaxed);
        let mut temp_name = std::ffi::OsString::from(".");
        temp_name.push(name);
        temp_name.push(format!(".{}-{n}.tmp", std::process::id()));
        let temp = dir.join(temp_name);
        match OpenOptions::new()
            .write(true)
            .read(true)
            .create_new(true)
            .open(&temp)
        {
            Ok(file) => return Ok((temp, file)),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(CaptureError::io(target, &e)),
        }
    }
}

/// A temporary file removed when dropped (unless kept by [`TemporaryFile::keep_as`]).
#[derive(Debug)]
pub(crate) struct TemporaryFile {
    path: Option<PathBuf>,
}

impl TemporaryFile {
    pub(crate) fn new(path: PathBuf) -> Self {
        Self { path: Some(path) }
    }

    /// Renames the file to `target` (replacing it): it is kept.
    pub(crate) fn keep_as(mut self, target: &Path) -> Result<(), CaptureError> {
        if let Some(temp) = self.path.take()
            && let Err(e) = std::fs::rename(&temp, target)
        {
            let _ = std::fs::remove_file(&temp);
            return Err(CaptureError::io(target, &e));
        }
        Ok(())
    }
}

impl Drop for TemporaryFile {
    fn drop(&mut self) {
        if let Some(temp) = self.path.take() {
            let _ = std::fs::remove_file(temp);
        }
    }
}

/// An output written to a temporary file beside `target`, renamed over it by
/// [`commit`](Self::commit); dropped without a commit, the temporary file is removed and
/// `target` is left as it was.
///
/// ```
/// use std::io::Write;
/// use angletrack::capture::OutputFile;
/// let path = std::env::temp_dir().join("angletrack_doc_output.txt");
/// std::fs::write(&path, "old").unwrap();
/// let mut out = OutputFile::create(&path).map_err(|e| e.to_string())?;
/// out.file().write_all(b"new").unwrap();
/// drop(out); // a failed run: the old file stays
/// assert_eq!(std::fs::read_to_string(&path).unwrap(), "old");
/// let mut out = OutputFile::create(&path).map_err(|e| e.to_string())?;
/// out.file().write_all(b"new").unwrap();
/// out.commit().map_err(|e| e.to_string())?;
/// assert_eq!(std::fs::read_to_string(&path).unwrap(), "new");
/// # std::fs::remove_file(&path).unwrap();
/// # Ok::<(), String>(())
/// ```
#[derive(Debug)]
pub struct OutputFile {
    target: PathBuf,
    file: File,
    temp: TemporaryFile,
}

impl OutputFile {
    /// A temporary file beside `target`, to be renamed to it.
    pub fn create(target: impl AsRef<Path>) -> Result<Self, CaptureError> {
        let target = target.as_ref();
        let (temp, file) = temporary_beside(target)?;
        Ok(Self {
            target: target.to_path_buf(),
            file,
            temp: TemporaryFile::new(temp),
        })
    }

    /// The temporary file to write to.
    pub fn file(&mut self) -> &mut File {
        &mut self.file
    }

    /// The target's path.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// The temporary file's path (for a writer that opens it itself).
    pub fn temporary(&self) -> &Path {
        self.temp.path.as_deref().unwrap_or(&self.target)
    }

    /// Flushes the file to the disk and renames it to the target, replacing it.
    pub fn commit(mut self) -> Result<(), CaptureError> {
        self.file
            .flush()
            .and_then(|()| self.file.sync_all())
            .map_err(|e| CaptureError::io(&self.target, &e))?;
        self.temp.keep_as(&self.target)
    }
}

/// Writes `bytes` to `path` through an [`OutputFile`] (all or nothing).
pub fn write_output(path: impl AsRef<Path>, bytes: &[u8]) -> Result<(), CaptureError> {
    let mut out = OutputFile::create(path)?;
    let target = out.target().to_path_buf();
    out.file()
        .write_all(bytes)
        .map_err(|e| CaptureError::io(&target, &e))?;
    out.commit()
}
