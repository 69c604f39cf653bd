//! Packaging mechanisms as FMUs: each built crate as an FMI 2.0 and an FMI 3.0 `.fmu`
//! (`archive`) carrying its binaries for every platform built (each checked by `binaries`;
//! the Mac ones given their install name and made universal by `macho`),
//! the model description and documentation its binary renders of itself, and its reference
//! results (`references`); and, when asked, the FMUs laid out as an FMI cross-check tree
//! (`cross_check`); each system of the workspace as an SSP of its components' FMUs (`ssp`),
//! and, when its components are all mechanisms, as one FMU like a mechanism's.

pub mod archive;
pub mod binaries;
pub mod cross_check;
pub mod macho;
pub mod references;
pub mod ssp;

use crate::build::workspace::mechanism_crates;
use crate::build::{
    built_libraries, built_system_fmus, built_systems, resolve, systems_named, Built, Flavor,
    Platforms,
};
use crate::system::{self, Declaration};
use mechfmu::contract::Version;
use mechfmu_host::description::ModelDescription;
use mechfmu_host::library::{Extra, Library};
use mechfmu_host::platform::Platform;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Builds the mechanism crates named (every one when `names` is empty) for `platforms` and
/// writes their FMUs of both versions under `out`, and as a cross-check tree under
/// `cross_check` when given, saying what it wrote; then each system named (every one when
/// `names` is empty) as `out/<System>.ssp`, its mechanisms built with the others, and as
/// one FMU of each version when its crate has the feature `fmu`.
pub fn write_fmus(
    names: &[String],
    out: &Path,
    manifest_path: Option<&Path>,
    flavor: Flavor,
    platforms: Platforms,
    cross_check: Option<&Path>,
) -> Result<(), String> {
    let started = Instant::now();
    let (platforms, missing) = resolve(platforms)?;
    for m in &missing {
        eprintln!("warning: {m}");
    }
    let (system_crates, mut mechanisms) = systems_named(names, manifest_path)?;
    // each system's declaration, read before its FMU's build overwrites the binary
    let systems: Vec<(Built, Declaration)> = built_systems(&system_crates, manifest_path, &flavor)?
        .into_iter()
        .map(|b| {
            let json = Library::open(&b.describing)?.text(Extra::SystemDeclaration)?;
            Declaration::parse(&json).map(|d| (b, d))
        })
        .collect::<Result<_, String>>()?;
    // before the mechanisms: it compiles the components under their feature `component`, and
    // the mechanisms' own build then makes them the mechanisms' FMUs again
    let system_fmus = built_system_fmus(&system_crates, manifest_path, &flavor, &platforms)?;
    // Named systems bring their mechanisms (no names: every mechanism is built anyway).
    if !names.is_empty() {
        for model in systems.iter().flat_map(|(_, d)| d.mechanisms()) {
            if !mechanisms.contains(&model) {
                mechanisms.push(model);
            }
        }
    }
    // Nothing to build: no mechanism named, or a workspace of systems alone (of FMU files)
    let nothing = match names.is_empty() {
        true => !systems.is_empty() && mechanism_crates(manifest_path)?.is_empty(),
        false => mechanisms.is_empty(),
    };
    let built = if nothing {
        Vec::new()
    } else {
        built_libraries(&mechanisms, manifest_path, &flavor, &platforms)?
    };
    std::fs::create_dir_all(out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    for b in built.iter().chain(&system_fmus) {
        for version in [Version::Fmi2, Version::Fmi3] {
            let packaged = package_fmu(b, &platforms, out, version)?;
            let folders: Vec<&str> = platforms.iter().map(|p| p.folder(version)).collect();
            println!(
                "{:<20} {:<8} {} ({} KiB): {}",
                b.krate.model,
                version.name(),
                packaged.path.display(),
                packaged.size.div_ceil(1024),
                folders.join(", ")
            );
            if let Some(root) = cross_check {
                cross_check::write_model(
                    root,
                    &b.krate.model,
                    version,
                    &platforms,
                    &packaged.path,
                    &packaged.references,
                )?;
            }
        }
    }
    let tuples: Vec<&str> = platforms.iter().map(|p| p.tuple()).collect();
    let fmus = built.len() + system_fmus.len();
    println!(
        "built {} mechanism{} and system{} as FMI 2.0 and FMI 3.0 FMUs for {} in {:.1} s",
        fmus,
        if fmus == 1 { "" } else { "s" },
        if fmus == 1 { "" } else { "s" },
        tuples.join(", "),
        started.elapsed().as_secs_f64()
    );
    if let Some(root) = cross_check {
        println!(
            "cross-check tree: {}",
            root.join("fmus/<2.0|3.0>/<cs|me>/<platform>")
                .join(cross_check::TOOL)
                .join(env!("CARGO_PKG_VERSION"))
                .display()
        );
    }
    for (b, declaration) in &systems {
        let crate_dir = b.krate.manifest.parent().unwrap_or(Path::new("."));
        let components = system::components(declaration, &folder(out, Version::Fmi2), crate_dir)?;
        system::check(declaration, &components)?;
        let path = out.join(format!("{}.ssp", declaration.name));
        ssp::write_ssp(&path, declaration, &components)?;
        println!(
            "{:<20} SSP 1.0  {} ({} KiB): {} components, {} parameter set{}",
            declaration.name,
            path.display(),
            std::fs::metadata(&path)
                .map_or(0, |m| m.len())
                .div_ceil(1024),
            components.len(),
            declaration.parameter_sets.len(),
            if declaration.parameter_sets.len() == 1 {
                ""
            } else {
                "s"
            }
        );
    }
    for m in &missing {
        println!("not built for {}: {}", m.platform.tuple(), m.what());
    }
    Ok(())
}

/// Where the FMUs of `version` go under the build's output folder `out`: FMI 2.0's in it,
/// FMI 3.0's in its `fmi3/` (the same file names, so an importer's instance names do not
/// depend on the version).
pub fn folder(out: &Path, version: Version) -> PathBuf {
    match version {
        Version::Fmi2 => out.to_path_buf(),
        Version::Fmi3 => out.join("fmi3"),
    }
}

/// An FMU written.
pub struct Packaged {
    pub path: PathBuf,
    /// Its size in bytes.
    pub size: u64,
    /// The reference files it carries (archive path, bytes).
    pub references: Vec<(String, Vec<u8>)>,
}

/// Packages the libraries of `built` for `platforms` as an FMU of `version` (in [`folder`]
/// of `out`): asks this machine's describing binary (the same declaration compiled with the
/// extras) for its modelDescription of that version, so the XML and the binaries can never
/// disagree, and for its documentation; checks every
/// binary (see [`binaries::check`]); adds the reference results found in the crate's
/// `reference/` (see [`references`]).
pub fn package_fmu(
    built: &Built,
    platforms: &[Platform],
    out: &Path,
    version: Version,
) -> Result<Packaged, String> {
    let model = &built.krate.model;
    let host = built.host_library();
    let library = Library::open(&built.describing)?;
    let xml = library.text(Extra::ModelDescription(version))?;
    let read = |path: &Path| {
        std::fs::read(path).map_err(|e| format!("cannot read {}: {e}", path.display()))
    };
    let host_exports = binaries::inspect(&read(host)?)
        .map_err(|e| format!("{}: {e}", host.display()))?
        .swap_remove(0)
        .exports;
    let shipped = shipped_binaries(built, platforms, version, &host_exports)?;
    let folder = folder(out, version);
    std::fs::create_dir_all(&folder)
        .map_err(|e| format!("cannot create {}: {e}", folder.display()))?;
    let path = folder.join(format!("{model}.fmu"));
    let contents = archive::Contents {
        model_description: &xml,
        binaries: shipped,
        extra: extra_files(
            model,
            &library,
            built.krate.manifest.parent(),
            version,
            &xml,
        )?,
    };
    archive::write_fmu(&path, &contents)
        .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    let size = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0);
    let references = contents
        .extra
        .into_iter()
        .filter(|(p, _)| p.starts_with(references::REFERENCE_DIR))
        .collect();
    Ok(Packaged {
        path,
        size,
        references,
    })
}

/// The binaries of `built` for `platforms` in an FMU of `version` (archive path, bytes), each
/// checked ([`binaries::check`]) against the exports of this machine's binary: a Mac dylib
/// with an install name of its own ([`binaries::install_name`]); in FMI 2.0, `darwin64`
/// holds both Mac binaries as one universal file where both are built (FMPy on Apple
/// silicon loads FMI 2.0 binaries from `darwin64`), beside `aarch64-darwin`'s own.
fn shipped_binaries(
    built: &Built,
    platforms: &[Platform],
    version: Version,
    host_exports: &[String],
) -> Result<Vec<(String, Vec<u8>)>, String> {
    let model = &built.krate.model;
    let refused = |what: &str, path: &Path, e: String| {
        format!(
            "the {what} binary of {model} ({}) cannot be shipped: {e}",
            path.display()
        )
    };
    let mut shipped = Vec::new();
    let mut macs = Vec::new();
    for &platform in platforms {
        let path = &built.libraries[&platform];
        let mut bytes =
            std::fs::read(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        let file_name = format!("{model}.{}", platform.extension());
        if platform.is_darwin() {
            macho::set_install_name(&mut bytes, &binaries::install_name(&file_name))
                .map_err(|e| refused(platform.tuple(), path, e))?;
        }
        binaries::check(&bytes, &[platform], host_exports)
            .map_err(|e| refused(platform.tuple(), path, e))?;
        if platform.is_darwin() {
            macs.push(bytes.clone());
        }
        let folder = platform.folder(version);
        shipped.push((format!("binaries/{folder}/{file_name}"), bytes));
    }
    if version == Version::Fmi2 && macs.len() == 2 {
        let slices: Vec<&[u8]> = macs.iter().map(Vec::as_slice).collect();
        let universal = macho::universal(&slices)?;
        let both = [Platform::X86_64Darwin, Platform::Aarch64Darwin];
        let darwin64 = &built.libraries[&Platform::X86_64Darwin];
        binaries::check(&universal, &both, host_exports)
            .map_err(|e| refused("universal macOS", darwin64, e))?;
        let folder = Platform::X86_64Darwin.folder(version);
        let entry = (shipped.iter_mut())
            .find(|(p, _)| p.starts_with(&format!("binaries/{folder}/")))
            .expect("the x86-64 Mac binary is shipped");
        entry.1 = universal;
    }
    Ok(shipped)
}

/// The files added to the archive of version `version` of `model` built into `library` from
/// the crate in `crate_dir`: `documentation/index.html` (rendered by the binary for that
/// version) and the crate's reference files (in an FMI 3.0 FMU, the columns of scalars that
/// are array elements there named as the elements, from its model description `xml`).
/// Sorted by archive path.
/// Where an FMI 3.0 FMU keeps its terminals (FMI 3.0 §2.4.9).
pub const TERMINALS_AND_ICONS: &str = "terminalsAndIcons/terminalsAndIcons.xml";

fn extra_files(
    model: &str,
    library: &Library,
    crate_dir: Option<&Path>,
    version: Version,
    xml: &str,
) -> Result<Vec<(String, Vec<u8>)>, String> {
    let mut files = vec![(
        "documentation/index.html".to_string(),
        library.text(Extra::Documentation(version))?.into_bytes(),
    )];
    if version == Version::Fmi3 {
        if let Some(terminals) = library.optional_text(Extra::TerminalsAndIcons)? {
            files.push((TERMINALS_AND_ICONS.to_string(), terminals.into_bytes()));
        }
    }
    if let Some(dir) = crate_dir {
        let mut found = references::reference_files(model, &dir.join("reference"))?;
        if version == Version::Fmi3 {
            let names = ModelDescription::parse(xml)?.element_names();
            for (path, bytes) in &mut found {
                if path.ends_with(".csv") {
                    *bytes = references::rename_columns(bytes, &names);
                }
            }
        }
        files.extend(found);
    }
    files.sort_by(|a, b| a.0.cmp(&b.0));
    Ok(files)
}
