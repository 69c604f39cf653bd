//! An FMU's binary loaded the way an importer loads it (`libloading`), and the texts a
//! binary mechfmu built with the runtime's `describe` feature renders of itself through the
//! documented extras of `export_fmu!`.

use mechfmu::contract::Version;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A loaded shared library. The function tables of [`crate::fmi2`] and [`crate::fmi3`] hold
/// on to it, so it stays loaded as long as anything can call into it.
pub struct Library {
    path: PathBuf,
    library: Arc<libloading::Library>,
}

/// One of the texts a binary built with the runtime's `describe` feature renders of itself
/// (a shipped binary has none).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Extra {
    /// Its model description of this version (`mechfmu_model_description`,
    /// `mechfmu_model_description_fmi3`): the XML `mechfmu build` packages.
    ModelDescription(Version),
    /// Its documentation page of this version (`mechfmu_documentation`,
    /// `mechfmu_documentation_fmi3`).
    Documentation(Version),
    /// Its interface page (`mechfmu_interface`): the Markdown of `docs/mechanisms/`.
    Interface,
    /// Its FMI 3.0 FMU's `terminalsAndIcons/terminalsAndIcons.xml`
    /// (`mechfmu_terminals_and_icons`), empty for a mechanism without terminals.
    TerminalsAndIcons,
    /// A system crate's declaration (`mechfmu_system_declaration`, of
    /// `mechfmu::export_system!`): the JSON `mechfmu build` packages the system from.
    SystemDeclaration,
}

impl Extra {
    /// The exported symbol.
    pub fn symbol(self) -> &'static str {
        match self {
            Extra::ModelDescription(Version::Fmi2) => "mechfmu_model_description",
            Extra::ModelDescription(Version::Fmi3) => "mechfmu_model_description_fmi3",
            Extra::Documentation(Version::Fmi2) => "mechfmu_documentation",
            Extra::Documentation(Version::Fmi3) => "mechfmu_documentation_fmi3",
            Extra::Interface => "mechfmu_interface",
            Extra::SystemDeclaration => "mechfmu_system_declaration",
            Extra::TerminalsAndIcons => "mechfmu_terminals_and_icons",
        }
    }

    /// What the messages call the text.
    fn what(self) -> &'static str {
        match self {
            Extra::ModelDescription(_) => "modelDescription",
            Extra::Documentation(_) => "documentation",
            Extra::Interface => "interface page",
            Extra::SystemDeclaration => "system declaration",
            Extra::TerminalsAndIcons => "terminals",
        }
    }
}

/// The signature of every documented extra: `mechfmu::export::write_text`'s buffer protocol.
type Render = unsafe extern "C" fn(*mut u8, usize) -> usize;

impl Library {
    /// Loads the shared library at `path` (a message naming it when it cannot be loaded).
    pub fn open(path: &Path) -> Result<Library, String> {
        // SAFETY: loading an FMU binary runs its initializers, which an importer has to
        // trust (mechfmu's are Rust's: none).
        let library = unsafe { libloading::Library::new(path) }
            .map_err(|e| format!("cannot load {}: {e}", path.display()))?;
        Ok(Library {
            path: path.to_path_buf(),
            library: Arc::new(library),
        })
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The library, for a function table to hold on to.
    pub(crate) fn shared(&self) -> Arc<libloading::Library> {
        Arc::clone(&self.library)
    }

    /// Whether the library exports `symbol`.
    pub fn exports(&self, symbol: &str) -> bool {
        // SAFETY: the symbol's address is looked up only, never called or read through.
        unsafe {
            self.library
                .get::<*const std::ffi::c_void>(symbol.as_bytes())
        }
        .is_ok()
    }

    /// The function exported as `name`.
    ///
    /// # Safety
    /// `F` is the function pointer type the symbol `name` has in the binary, and the
    /// pointer is called only while the library stays loaded (held by the caller's table).
    pub(crate) unsafe fn function<F: Copy>(&self, name: &str) -> Result<F, libloading::Error> {
        // SAFETY: the caller's promise.
        unsafe { self.library.get::<F>(name.as_bytes()) }.map(|symbol| *symbol)
    }

    /// The text the binary renders of itself through one of the documented extras, with
    /// the buffer protocol of `mechfmu::export::write_text` (a NULL buffer asks for the
    /// length, then a buffer of that length plus the NUL). A binary that cannot render it
    /// answers `error: ...`, which becomes the message.
    pub fn text(&self, extra: Extra) -> Result<String, String> {
        self.optional_text(extra)?
            .ok_or_else(|| format!("{} rendered no {}", self.path.display(), extra.what()))
    }

    /// [`Library::text`], `None` for an empty text (a mechanism without terminals).
    pub fn optional_text(&self, extra: Extra) -> Result<Option<String>, String> {
        let (symbol, what, path) = (extra.symbol(), extra.what(), self.path.display());
        // SAFETY: the extras are exported by `export_fmu!` and `export_system!` with this
        // signature.
        let render: Render = unsafe { self.function(symbol) }.map_err(|e| {
            format!(
                "{path} does not export {symbol} (a shipped FMU binary, which carries the FMI \
                 functions alone, or not built by mechfmu with the runtime's `describe` \
                 feature): {e}"
            )
        })?;
        // SAFETY: `write_text`'s protocol: NULL asks for the length; then a buffer with room
        // for the text and its NUL.
        let len = unsafe { render(std::ptr::null_mut(), 0) };
        if len == 0 {
            return Ok(None);
        }
        let mut buf = vec![0u8; len + 1];
        let written = unsafe { render(buf.as_mut_ptr(), buf.len()) };
        if written != len {
            return Err(format!("{path} rendered no {what}"));
        }
        buf.truncate(len);
        let text = String::from_utf8(buf).map_err(|e| format!("{what} is not UTF-8: {e}"))?;
        match text.strip_prefix("error: ") {
            Some(message) => Err(format!("{path}: cannot render its {what}: {message}")),
            None => Ok(Some(text)),
        }
    }
}
