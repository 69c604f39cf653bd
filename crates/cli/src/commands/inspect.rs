//! `mechfmu inspect FMU...`: the binaries an FMU carries, and for each the platform it is
//! built for, the libraries it loads and the functions it exports and imports (for a Mac
//! dylib also its install name, minimum macOS and code signature); any FMU, ours or not.

use crate::package::binaries::{foreign_dependencies, inspect, Facts};
use crate::package::macho::Signature;
use mechfmu_host::archive;
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct Args {
    /// The FMU files.
    #[arg(required = true)]
    fmus: Vec<PathBuf>,
    /// Print JSON (one object per FMU, in a list) instead of text.
    #[arg(long)]
    json: bool,
}

pub fn run(args: Args) -> Result<(), String> {
    let mut reports = Vec::new();
    let mut problems = 0;
    for fmu in &args.fmus {
        let report = binaries_of(fmu)?;
        problems += report["binaries"]
            .as_array()
            .into_iter()
            .flatten()
            .filter(|b| b["problem"].is_string())
            .count();
        if !args.json {
            print_text(fmu, &report);
        }
        reports.push(report);
    }
    if args.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&reports).expect("JSON values serialize")
        );
    }
    if problems > 0 {
        return Err(format!(
            "{problems} binar{} with a problem",
            if problems == 1 { "y" } else { "ies" }
        ));
    }
    Ok(())
}

/// `{"fmu": path, "binaries": [{"path", "folder", "size", "platform", "dependencies",
/// "foreign_dependencies", "exports", "imports", "problem"}]}`, one entry per file under
/// `binaries/` (per slice of a universal Mach-O file, with `"slice": true`), a Mac binary's
/// with its `"install_name"`, `"minimum_macos"` and `"signature"` too.
fn binaries_of(fmu: &Path) -> Result<serde_json::Value, String> {
    let mut binaries = Vec::new();
    for file in archive::binaries(fmu)? {
        let binary = serde_json::json!({
            "path": file.path,
            "folder": file.folder,
            "size": file.bytes.len(),
        });
        match inspect(&file.bytes) {
            Ok(all) => {
                let universal = all.len() > 1;
                for facts in all {
                    let mut slice = described(binary.clone(), facts);
                    if universal {
                        slice["slice"] = true.into();
                    }
                    binaries.push(slice);
                }
            }
            Err(e) => {
                let mut binary = binary;
                binary["problem"] = e.into();
                binaries.push(binary);
            }
        }
    }
    Ok(serde_json::json!({ "fmu": fmu.display().to_string(), "binaries": binaries }))
}

/// `binary` with what `facts` says.
fn described(mut binary: serde_json::Value, facts: Facts) -> serde_json::Value {
    binary["platform"] = facts.platform.map(|p| p.tuple()).into();
    binary["foreign_dependencies"] = match facts.platform {
        Some(p) => foreign_dependencies(&facts, p).into(),
        None => serde_json::Value::Null,
    };
    if let Some(mac) = &facts.mac {
        binary["install_name"] = mac.install_name.clone().into();
        binary["minimum_macos"] = mac
            .minimum_macos
            .map(|(a, b, c)| format!("{a}.{b}.{c}"))
            .into();
        binary["signature"] = match &mac.signature {
            Signature::Missing => "none".into(),
            Signature::Valid { adhoc: true, .. } => "valid (ad hoc)".into(),
            Signature::Valid { adhoc: false, .. } => "valid".into(),
            Signature::Invalid(why) => format!("invalid: {why}").into(),
        };
    }
    binary["dependencies"] = facts.dependencies.into();
    binary["exports"] = facts.exports.into();
    binary["imports"] = facts.imports.into();
    binary
}

fn print_text(fmu: &Path, report: &serde_json::Value) {
    println!("{}", fmu.display());
    let binaries = report["binaries"].as_array().cloned().unwrap_or_default();
    if binaries.is_empty() {
        println!("  no binaries");
    }
    for b in binaries {
        let strings = |key: &str| -> Vec<String> {
            b[key]
                .as_array()
                .into_iter()
                .flatten()
                .filter_map(|v| v.as_str().map(String::from))
                .collect()
        };
        println!(
            "  {} ({} bytes): {}",
            b["path"].as_str().unwrap_or(""),
            b["size"],
            b["platform"].as_str().unwrap_or("unknown platform")
        );
        if let Some(problem) = b["problem"].as_str() {
            println!("    problem: {problem}");
            continue;
        }
        println!("    loads: {}", strings("dependencies").join(", "));
        let foreign = strings("foreign_dependencies");
        if !foreign.is_empty() {
            println!("    not part of every such system: {}", foreign.join(", "));
        }
        println!("    exports {} functions", strings("exports").len());
        if let Some(name) = b["install_name"].as_str() {
            println!(
                "    install name {name}, macOS {} or newer, code signature: {}",
                b["minimum_macos"].as_str().unwrap_or("(not stated)"),
                b["signature"].as_str().unwrap_or("")
            );
        }
    }
}
