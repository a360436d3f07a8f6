//! Finding the bytes of mesh files referenced by a URDF.

use std::borrow::Cow;
use std::collections::HashMap;
use std::path::{Component, Path, PathBuf};
use std::sync::{Arc, OnceLock};

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

/// Resolves mesh files on disk, finding ROS packages as `rospack` / `ament` do.
///
/// - Relative paths (and `file://` URIs with a relative path) are taken relative to the base
///   directory (normally the URDF file's directory); absolute paths and `file:///abs/path` as is.
/// - `package://NAME/rest` looks for package `NAME`, in this order:
///   1. a directory registered with [`FileResolver::with_package`];
///   2. the ancestors of the base directory (itself included): one whose `package.xml` gives
///      `<name>NAME</name>`, or, with no `package.xml`, whose folder is called `NAME` — so
///      `pkg/urdf/robot.urdf` finds its own meshes without configuration;
///   3. the packages under the search roots: the folder holding the package of step 2 (the
///      workspace `src` folder, so sibling packages are found), roots added with
///      [`FileResolver::with_search_root`], and those of [`FileResolver::with_ros_package_path`]
///      (`ROS_PACKAGE_PATH`, and `share/` of each `AMENT_PREFIX_PATH` prefix). A root is
///      crawled like `rospack` does, [`MAX_CRAWL_DEPTH`] levels deep, hidden folders skipped,
///      not descending into a package; a package is known by its `package.xml` name (or its
///      folder name if the file has none).
///
///   A package found nowhere is [`CoreError::PackageNotFound`] listing every directory
///   searched.
/// - Other schemes (`http://`, ...) are not supported and report [`CoreError::MeshNotFound`].
///
/// Percent-encoding in URIs is not decoded. The package index of the search roots is built on
/// first use and kept (clones made after that share nothing but a copy of it).
#[derive(Clone, Debug, Default)]
pub struct FileResolver {
    base_dir: PathBuf,
    packages: HashMap<String, PathBuf>,
    roots: Vec<PathBuf>,
    index: OnceLock<PackageIndex>,
}

/// How deep below a search root packages are looked for (as `rospack`'s crawl, which has no
/// limit, but bounded so a root such as `/` cannot make a load take minutes).
pub const MAX_CRAWL_DEPTH: usize = 6;

/// Package name → directory.
#[derive(Clone, Debug, Default)]
struct PackageIndex {
    packages: HashMap<String, PathBuf>,
}

/// The `<name>` of a `package.xml` in `dir`, if the file exists and names one.
fn package_name(dir: &Path) -> Option<String> {
    let bytes = std::fs::read(dir.join("package.xml")).ok()?;
    let limits = super::XmlLimits { max_bytes: 1 << 20, ..super::XmlLimits::default() };
    super::limits::check_xml(&bytes, &limits, "package.xml", |reason| CoreError::MalformedUrdf { reason }).ok()?;
    let mut reader = quick_xml::Reader::from_reader(bytes.as_slice());
    let mut buf = Vec::new();
    let mut depth = 0usize;
    let mut in_name = false;
    loop {
        match reader.read_event_into(&mut buf).ok()? {
            quick_xml::events::Event::Start(e) => {
                depth += 1;
                in_name = depth == 2 && e.name().as_ref() == b"name";
            }
            quick_xml::events::Event::Text(t) if in_name => {
                let name = t.decode().ok()?.trim().to_string();
                return (!name.is_empty()).then_some(name);
            }
            quick_xml::events::Event::End(_) => {
                depth = depth.saturating_sub(1);
                in_name = false;
            }
            quick_xml::events::Event::Eof => return None,
            _ => {}
        }
        buf.clear();
    }
}

/// The package rooted at `dir`: its `package.xml` name, or its folder name if `dir` has a
/// `package.xml` without a usable name. `None` if `dir` is not a package.
fn package_at(dir: &Path) -> Option<String> {
    if !dir.join("package.xml").is_file() {
        return None;
    }
    package_name(dir).or_else(|| dir.file_name().map(|n| n.to_string_lossy().into_owned()))
}

/// Adds the packages below `root` (breadth first, first found wins).
fn crawl(root: &Path, index: &mut PackageIndex) {
    let mut queue = std::collections::VecDeque::from([(root.to_path_buf(), 0usize)]);
    while let Some((dir, depth)) = queue.pop_front() {
        if let Some(name) = package_at(&dir) {
            index.packages.entry(name).or_insert(dir);
            continue;
        }
        if depth >= MAX_CRAWL_DEPTH || dir.join("CATKIN_IGNORE").exists() || dir.join("COLCON_IGNORE").exists() {
            continue;
        }
        let Ok(entries) = std::fs::read_dir(&dir) else { continue };
        let mut subdirs: Vec<PathBuf> = entries
            .filter_map(|e| e.ok())
            .filter(|e| e.file_type().is_ok_and(|t| t.is_dir()))
            .filter(|e| !e.file_name().to_string_lossy().starts_with('.'))
            .map(|e| e.path())
            .collect();
        subdirs.sort();
        queue.extend(subdirs.into_iter().map(|d| (d, depth + 1)));
    }
}

impl FileResolver {
    /// A resolver for paths relative to `base_dir`, with no search roots.
    pub fn new(base_dir: impl Into<PathBuf>) -> Self {
        Self { base_dir: base_dir.into(), ..Self::default() }
    }

    /// Registers the root directory of a ROS package for `package://name/...` URIs.
    pub fn with_package(mut self, name: impl Into<String>, dir: impl Into<PathBuf>) -> Self {
        self.packages.insert(name.into(), dir.into());
        self.index = OnceLock::new();
        self
    }

    /// Adds a directory under which packages are looked for by their `package.xml` name
    /// (a workspace `src` folder, an install `share` folder, a folder of robot descriptions).
    pub fn with_search_root(mut self, root: impl Into<PathBuf>) -> Self {
        self.roots.push(root.into());
        self.index = OnceLock::new();
        self
    }

    /// Adds the search roots of the environment: each entry of `ROS_PACKAGE_PATH` (ROS 1) and
    /// `share/` of each entry of `AMENT_PREFIX_PATH` (ROS 2). Unset variables add nothing.
    pub fn with_ros_package_path(mut self) -> Self {
        if let Some(paths) = std::env::var_os("ROS_PACKAGE_PATH") {
            self.roots.extend(std::env::split_paths(&paths).filter(|p| !p.as_os_str().is_empty()));
        }
        if let Some(paths) = std::env::var_os("AMENT_PREFIX_PATH") {
            self.roots
                .extend(std::env::split_paths(&paths).filter(|p| !p.as_os_str().is_empty()).map(|p| p.join("share")));
        }
        self.index = OnceLock::new();
        self
    }

    /// The directory relative paths are resolved against.
    pub fn base_dir(&self) -> &Path {
        &self.base_dir
    }

    /// The search roots, in order (see [`FileResolver::with_search_root`]).
    pub fn search_roots(&self) -> &[PathBuf] {
        &self.roots
    }

    /// The nearest ancestor of the base directory (itself included) that is a package,
    /// with its name.
    fn own_package(&self) -> Option<(String, PathBuf)> {
        self.base_dir.ancestors().find_map(|a| package_at(a).map(|n| (n, a.to_path_buf())))
    }

    fn index(&self) -> &PackageIndex {
        self.index.get_or_init(|| {
            let mut index = PackageIndex::default();
            if let Some(parent) = self.own_package().and_then(|(_, dir)| dir.parent().map(Path::to_path_buf)) {
                crawl(&parent, &mut index);
            }
            for root in &self.roots {
                crawl(root, &mut index);
            }
            index
        })
    }

    /// The root directory of package `name`, searched as in the [type docs](FileResolver).
    ///
    /// # Errors
    /// [`CoreError::PackageNotFound`] listing every directory searched (`uri` names the
    /// reference that needed it).
    pub fn package_dir(&self, name: &str, uri: &str) -> Result<PathBuf> {
        if let Some(dir) = self.packages.get(name) {
            return Ok(dir.clone());
        }
        let mut searched: Vec<PathBuf> = Vec::new();
        for a in self.base_dir.ancestors() {
            searched.push(a.to_path_buf());
            match package_at(a) {
                Some(n) if n == name => return Ok(a.to_path_buf()),
                None if a.file_name().is_some_and(|n| n == name) => return Ok(a.to_path_buf()),
                _ => {}
            }
        }
        if let Some(dir) = self.index().packages.get(name) {
            return Ok(dir.clone());
        }
        if let Some(parent) = self.own_package().and_then(|(_, dir)| dir.parent().map(Path::to_path_buf)) {
            searched.push(parent);
        }
        searched.extend(self.roots.iter().cloned());
        Err(CoreError::PackageNotFound { package: name.to_string(), uri: uri.to_string(), searched })
    }

    /// The file `uri` refers to.
    ///
    /// # Errors
    /// [`CoreError::MeshNotFound`] if the URI has an unsupported scheme;
    /// [`CoreError::PackageNotFound`] if it names a package found nowhere.
    pub fn path_for(&self, uri: &str) -> Result<PathBuf> {
        let not_found = || CoreError::MeshNotFound { path: PathBuf::from(uri) };
        if let Some(rest) = uri.strip_prefix("package://") {
            let (package, rel) = rest.split_once('/').ok_or_else(not_found)?;
            return Ok(self.package_dir(package, uri)?.join(rel));
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
        assert!(matches!(r.path_for("package://nope/a.stl"), Err(CoreError::PackageNotFound { .. })));
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
