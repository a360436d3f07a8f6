//! Finding the bytes of mesh files referenced by a URDF.

use std::borrow::Cow;
use std::collections::HashMap;
use std::path::{Component, Path, PathBuf};
use std::sync::Arc;

use crate::error::{CoreError, Result};

/// Turns a URDF mesh `filename` (a relative or absolute path, a `package://` or a `file://`
/// URI) into the file's bytes.
///
/// Implement it to load assets from anywhere (an archive, embedded bytes, a network cache).
/// The trait is object-safe; loaders take `&dyn MeshResolver`.
pub trait MeshResolver: Send + Sync {
    /// The bytes of the mesh file named `uri` exactly as written in the URDF.
    ///
    /// # Errors
    /// [`CoreError::MeshNotFound`] if there is no such file; [`CoreError::Io`] if it exists but
    /// cannot be read.
    fn resolve(&self, uri: &str) -> Result<Cow<'_, [u8]>>;
}

impl<R: MeshResolver + ?Sized> MeshResolver for &R {
    fn resolve(&self, uri: &str) -> Result<Cow<'_, [u8]>> {
        (**self).resolve(uri)
    }
}

impl<R: MeshResolver + ?Sized> MeshResolver for Box<R> {
    fn resolve(&self, uri: &str) -> Result<Cow<'_, [u8]>> {
        (**self).resolve(uri)
    }
}

impl<R: MeshResolver + ?Sized> MeshResolver for Arc<R> {
    fn resolve(&self, uri: &str) -> Result<Cow<'_, [u8]>> {
        (**self).resolve(uri)
    }
}

/// Resolves mesh files on disk.
///
/// - Relative paths (and `file://` URIs with a relative path) are taken relative to the base
///   directory (normally the URDF file's directory); absolute paths and `file:///abs/path` as is.
/// - `package://name/rest` uses the directory registered for `name` with
///   [`FileResolver::with_package`]. Unregistered packages fall back to the ROS layout: the
///   nearest ancestor of the base directory (itself included) whose folder is called `name`,
///   so `pkg/urdf/robot.urdf` finds `package://pkg/meshes/x.stl` without configuration.
/// - Other schemes (`http://`, ...) are not supported and report [`CoreError::MeshNotFound`].
///
/// Percent-encoding in URIs is not decoded.
#[derive(Clone, Debug, Default)]
pub struct FileResolver {
    base_dir: PathBuf,
    packages: HashMap<String, PathBuf>,
}

impl FileResolver {
    /// A resolver for paths relative to `base_dir`.
    pub fn new(base_dir: impl Into<PathBuf>) -> Self {
        Self { base_dir: base_dir.into(), packages: HashMap::new() }
    }

    /// Registers the root directory of a ROS package for `package://name/...` URIs.
    pub fn with_package(mut self, name: impl Into<String>, dir: impl Into<PathBuf>) -> Self {
        self.packages.insert(name.into(), dir.into());
        self
    }

    /// The directory relative paths are resolved against.
    pub fn base_dir(&self) -> &Path {
        &self.base_dir
    }

    /// The file `uri` refers to.
    ///
    /// # Errors
    /// [`CoreError::MeshNotFound`] if the URI has an unsupported scheme or names an
    /// unregistered package that no ancestor of the base directory matches.
    pub fn path_for(&self, uri: &str) -> Result<PathBuf> {
        let not_found = || CoreError::MeshNotFound { path: PathBuf::from(uri) };
        if let Some(rest) = uri.strip_prefix("package://") {
            let (package, rel) = rest.split_once('/').ok_or_else(not_found)?;
            if let Some(dir) = self.packages.get(package) {
                return Ok(dir.join(rel));
            }
            return self
                .base_dir
                .ancestors()
                .find(|a| a.file_name().is_some_and(|n| n == package))
                .map(|a| a.join(rel))
                .ok_or_else(not_found);
        }
        let path = if let Some(rest) = uri.strip_prefix("file://") {
            // `file:///abs` keeps its leading slash; `file://localhost/abs` names the local host.
            rest.strip_prefix("localhost").unwrap_or(rest)
        } else if uri.contains("://") {
            return Err(not_found());
        } else {
            uri
        };
        let path = Path::new(path);
        Ok(if path.is_absolute() { path.to_path_buf() } else { self.base_dir.join(path) })
    }
}

impl MeshResolver for FileResolver {
    fn resolve(&self, uri: &str) -> Result<Cow<'_, [u8]>> {
        let path = self.path_for(uri)?;
        match std::fs::read(&path) {
            Ok(bytes) => Ok(Cow::Owned(bytes)),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Err(CoreError::MeshNotFound { path }),
            Err(source) => Err(CoreError::Io { path, source }),
        }
    }
}

/// Mesh files held in memory, keyed by the `filename` written in the URDF, so robots and
/// their assets can ship inside a binary and load with no file system access.
///
/// A URI is looked up exactly first; if absent, a normalised form is tried: `file://` removed,
/// `.` components dropped and `a/../` collapsed, for both the URI and the stored keys (so
/// `./meshes/a.stl` finds `meshes/a.stl`).
#[derive(Clone, Debug, Default)]
pub struct InMemoryResolver {
    files: HashMap<String, Vec<u8>>,
}

impl InMemoryResolver {
    /// An empty resolver.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds (or replaces) a file.
    pub fn insert(&mut self, key: impl Into<String>, bytes: impl Into<Vec<u8>>) {
        self.files.insert(key.into(), bytes.into());
    }

    /// Adds (or replaces) a file, builder style.
    pub fn with_file(mut self, key: impl Into<String>, bytes: impl Into<Vec<u8>>) -> Self {
        self.insert(key, bytes);
        self
    }

    /// Number of files held.
    pub fn len(&self) -> usize {
        self.files.len()
    }

    /// True if no file is held.
    pub fn is_empty(&self) -> bool {
        self.files.is_empty()
    }
}

impl From<HashMap<String, Vec<u8>>> for InMemoryResolver {
    fn from(files: HashMap<String, Vec<u8>>) -> Self {
        Self { files }
    }
}

/// `file://` stripped, `.` dropped and `x/..` collapsed.
fn normalise(uri: &str) -> String {
    let s = uri.strip_prefix("file://").unwrap_or(uri);
    let (prefix, path) = match s.split_once("://") {
        Some((scheme, rest)) => (format!("{scheme}://"), rest),
        None => (String::new(), s),
    };
    let mut parts: Vec<String> = Vec::new();
    for c in Path::new(path).components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir if parts.last().is_some_and(|p| p != ".." && p != "/") => {
                parts.pop();
            }
            Component::RootDir => parts.push("/".to_string()),
            other => parts.push(other.as_os_str().to_string_lossy().into_owned()),
        }
    }
    let joined = match parts.first().map(String::as_str) {
        Some("/") => format!("/{}", parts[1..].join("/")),
        _ => parts.join("/"),
    };
    prefix + &joined
}

impl MeshResolver for InMemoryResolver {
    fn resolve(&self, uri: &str) -> Result<Cow<'_, [u8]>> {
        if let Some(bytes) = self.files.get(uri) {
            return Ok(Cow::Borrowed(bytes));
        }
        let wanted = normalise(uri);
        self.files
            .iter()
            .find(|(k, _)| normalise(k) == wanted)
            .map(|(_, v)| Cow::Borrowed(v.as_slice()))
            .ok_or_else(|| CoreError::MeshNotFound { path: PathBuf::from(uri) })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalisation() {
        assert_eq!(normalise("./meshes/a.stl"), "meshes/a.stl");
        assert_eq!(normalise("file://meshes/x/../a.stl"), "meshes/a.stl");
        assert_eq!(normalise("file:///abs/a.stl"), "/abs/a.stl");
        assert_eq!(normalise("package://pkg/./m/a.stl"), "package://pkg/m/a.stl");
        assert_eq!(normalise("../a.stl"), "../a.stl");
    }

    #[test]
    fn file_resolver_paths() {
        let r = FileResolver::new("/robots/my_pkg/urdf").with_package("other", "/opt/other");
        assert_eq!(r.path_for("m/a.stl").unwrap(), Path::new("/robots/my_pkg/urdf/m/a.stl"));
        assert_eq!(r.path_for("/abs/a.stl").unwrap(), Path::new("/abs/a.stl"));
        assert_eq!(r.path_for("file:///abs/a.stl").unwrap(), Path::new("/abs/a.stl"));
        assert_eq!(r.path_for("package://other/m/a.stl").unwrap(), Path::new("/opt/other/m/a.stl"));
        assert_eq!(r.path_for("package://my_pkg/meshes/a.stl").unwrap(), Path::new("/robots/my_pkg/meshes/a.stl"));
        assert!(matches!(r.path_for("package://nope/a.stl"), Err(CoreError::MeshNotFound { .. })));
        assert!(matches!(r.path_for("http://example.com/a.stl"), Err(CoreError::MeshNotFound { .. })));
    }

    #[test]
    fn in_memory_lookup() {
        let r = InMemoryResolver::new().with_file("meshes/a.stl", vec![1u8, 2, 3]);
        assert_eq!(&*r.resolve("meshes/a.stl").unwrap(), &[1, 2, 3]);
        assert_eq!(&*r.resolve("./meshes/a.stl").unwrap(), &[1, 2, 3]);
        assert!(matches!(r.resolve("meshes/b.stl"), Err(CoreError::MeshNotFound { .. })));
        let dynamic: &dyn MeshResolver = &r;
        assert_eq!(dynamic.resolve("file://meshes/a.stl").unwrap().len(), 3);
    }
}
