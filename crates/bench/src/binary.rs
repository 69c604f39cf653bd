//! A built FMU as the benchmark loads it: its binary through `mechfmu-host`, read with the
//! FMI 2.0 model description of its archive, and the FMI 3.0 side of the same binary (its
//! FMI 3.0 functions and the FMI 3.0 model description it renders of itself).

use mechfmu::contract::Version;
use mechfmu_host::description::ModelDescription;
use mechfmu_host::fmi2::functions::Functions;
use mechfmu_host::fmi3::functions::Functions as Fmi3Functions;
use mechfmu_host::library::{Extra, Library};
use std::path::{Path, PathBuf};

/// A loaded FMU binary and its description.
pub struct Binary {
    pub path: PathBuf,
    pub description: ModelDescription,
    /// Its FMI 2.0 functions (with Model Exchange's and the benchmark entry points where it
    /// exports them).
    pub fmi2: Functions,
    /// The FMI 3.0 side of the same binary (None: it exports no FMI 3.0 functions).
    pub fmi3: Option<Fmi3>,
}

/// A binary's FMI 3.0 side: its functions, its instantiation token and the scalar
/// variables of its FMI 3.0 modelDescription (name, value reference).
pub struct Fmi3 {
    pub functions: Fmi3Functions,
    pub token: String,
    pub scalars: Vec<(String, u32)>,
}

impl Binary {
    /// Loads the `.so` at `so` and reads `xml` (the archive's modelDescription.xml).
    pub fn load(so: &Path, xml: &Path) -> Result<Binary, String> {
        let text = std::fs::read_to_string(xml)
            .map_err(|e| format!("cannot read {}: {e}", xml.display()))?;
        let description = ModelDescription::parse(&text)?;
        let library = Library::open(so)?;
        Ok(Binary {
            path: so.to_path_buf(),
            description,
            fmi2: Functions::load(&library)?,
            fmi3: Fmi3::load(&library)?,
        })
    }

    /// The value reference of the FMU's first output: what an importer's loop reads.
    pub fn first_output(&self) -> Result<u32, String> {
        (self.description.with_causality("output").first())
            .map(|v| v.vr)
            .ok_or_else(|| "the FMU has no output".into())
    }

    /// Whether the binary exports mechfmu's counters and `mechfmu_bench`.
    pub fn has_counters(&self) -> bool {
        self.fmi2.has_bench()
    }
}

impl Fmi3 {
    /// The FMI 3.0 side of `library`; None where it exports no FMI 3.0 functions or no
    /// `mechfmu_model_description_fmi3` (a binary built before them).
    fn load(library: &Library) -> Result<Option<Fmi3>, String> {
        let extra = Extra::ModelDescription(Version::Fmi3);
        let Some(functions) = Fmi3Functions::load(library) else {
            return Ok(None);
        };
        if !library.exports(extra.symbol()) {
            return Ok(None);
        }
        let description = ModelDescription::parse(&library.text(extra)?)?;
        let scalars = (description.variables.into_iter())
            .filter(|v| v.dimensions.is_empty())
            .map(|v| (v.name, v.vr))
            .collect();
        Ok(Some(Fmi3 {
            functions,
            token: description.token,
            scalars,
        }))
    }
}
