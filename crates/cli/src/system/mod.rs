//! The systems of a workspace as `mechfmu build` packages them: a system crate's declaration
//! (the JSON its binary gives, `mechfmu::export_system!`), its components resolved to FMU
//! files with their model descriptions, and the checks the declaration could not make at
//! compile time (an FMU file's variables, loops of direct feedthrough), with the messages of
//! `mechfmu::system`.

mod checks;

pub use checks::check;

use mechfmu_host::description::ModelDescription;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// A system's declaration, as `mechfmu::system::declaration_json` writes it.
#[derive(Clone, Debug, Deserialize)]
pub struct Declaration {
    pub name: String,
    pub description: String,
    pub experiment: Experiment,
    pub components: Vec<ComponentDeclaration>,
    pub connections: Vec<Connection>,
    /// `default` first; each set as applied (the default set's values with its own over
    /// them).
    pub parameter_sets: Vec<ParameterSet>,
}

#[derive(Clone, Copy, Debug, Deserialize)]
pub struct Experiment {
    pub start: f64,
    pub stop: f64,
    pub step: f64,
    pub tolerance: f64,
}

#[derive(Clone, Debug, Deserialize)]
pub struct ComponentDeclaration {
    pub name: String,
    pub description: String,
    /// A mechanism's model identifier.
    pub model: Option<String>,
    /// An FMU file's path, from the system crate's folder.
    pub fmu: Option<String>,
}

/// `(component, variable)`.
pub type Port = (String, String);

#[derive(Clone, Debug, Deserialize)]
pub struct Connection {
    pub from: Port,
    pub to: Port,
}

#[derive(Clone, Debug, Deserialize)]
pub struct ParameterSet {
    pub name: String,
    pub description: String,
    /// `(component, variable, value)`.
    pub values: Vec<(String, String, f64)>,
}

impl Declaration {
    pub fn parse(json: &str) -> Result<Declaration, String> {
        serde_json::from_str(json)
            .map_err(|e| format!("the system declaration does not parse: {e}"))
    }

    /// The mechanisms the system is made of (their model identifiers, each once).
    pub fn mechanisms(&self) -> Vec<String> {
        let mut models: Vec<String> = Vec::new();
        for model in self.components.iter().filter_map(|c| c.model.clone()) {
            if !models.contains(&model) {
                models.push(model);
            }
        }
        models
    }
}

/// A component with the FMU it is.
pub struct Component {
    pub declaration: ComponentDeclaration,
    /// The FMU file.
    pub path: PathBuf,
    pub description: ModelDescription,
}

impl Component {
    /// The FMU's file name (`Oscillator.fmu`).
    pub fn file_name(&self) -> String {
        self.path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default()
    }
}

/// The components of `system` as FMI 2.0 FMU files: a mechanism's is `<fmu_dir>/<Model>.fmu`
/// (built before), an FMU file's is its path from `crate_dir`; each with its model
/// description.
pub fn components(
    system: &Declaration,
    fmu_dir: &Path,
    crate_dir: &Path,
) -> Result<Vec<Component>, String> {
    system
        .components
        .iter()
        .map(|c| {
            let path = match (&c.model, &c.fmu) {
                (Some(model), _) => fmu_dir.join(format!("{model}.fmu")),
                (None, Some(file)) => crate_dir.join(file),
                (None, None) => {
                    return Err(format!(
                        "component `{}` is neither a mechanism nor an FMU",
                        c.name
                    ))
                }
            };
            let description = read_description(&path)
                .map_err(|e| format!("system `{}`: component `{}`: {e}", system.name, c.name))?;
            Ok(Component {
                declaration: c.clone(),
                path,
                description,
            })
        })
        .collect()
}

/// The model description inside the FMU at `path`.
fn read_description(path: &Path) -> Result<ModelDescription, String> {
    let file =
        std::fs::File::open(path).map_err(|e| format!("cannot open {}: {e}", path.display()))?;
    let mut zip = zip::ZipArchive::new(file)
        .map_err(|e| format!("{} is not an FMU (not a zip archive): {e}", path.display()))?;
    let mut xml = String::new();
    std::io::Read::read_to_string(
        &mut zip
            .by_name("modelDescription.xml")
            .map_err(|e| format!("{} has no modelDescription.xml: {e}", path.display()))?,
        &mut xml,
    )
    .map_err(|e| {
        format!(
            "cannot read the modelDescription.xml of {}: {e}",
            path.display()
        )
    })?;
    ModelDescription::parse(&xml).map_err(|e| format!("{}: {e}", path.display()))
}
