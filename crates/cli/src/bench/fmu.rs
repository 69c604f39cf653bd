//! A built FMU loaded the way an importer loads it: the `.so` from the `.fmu` archive through
//! `libloading` ([`crate::fmi2_library`]), the FMI functions by their C names, the variables
//! from its modelDescription.xml. Nothing of the mechanism's Rust crate is linked.

#![allow(non_upper_case_globals)]

use crate::fmi2_library::{
    self, CoSimulation, Component, GetStates, NewDiscreteStates, SetStates, SetTime,
};
use mechfmu::fmi2::ffi::*;
use mechfmu_testkit::harness::MessageLog;
use quick_xml::events::Event;
use quick_xml::{Reader, XmlVersion};
use std::ffi::CString;
use std::io::Read;
use std::path::{Path, PathBuf};

/// A variable of the modelDescription.
#[derive(Clone, Debug, PartialEq)]
pub struct Variable {
    pub name: String,
    pub vr: fmi2ValueReference,
    pub causality: String,
    pub variability: String,
    pub start: Option<f64>,
}

/// What the benchmark needs from a modelDescription.xml.
#[derive(Clone, Debug, PartialEq)]
pub struct Description {
    pub model_identifier: String,
    pub guid: String,
    pub variables: Vec<Variable>,
    /// `DefaultExperiment`: start, stop, step size, tolerance.
    pub start: f64,
    pub stop: f64,
    pub step: f64,
    pub tolerance: f64,
    /// Whether the FMU declares Model Exchange (a `ModelExchange` element).
    pub model_exchange: bool,
    /// The number of continuous states (the `Unknown`s of `ModelStructure/Derivatives`).
    pub states: usize,
}

impl Description {
    pub fn parse(xml: &str) -> Result<Description, String> {
        let mut reader = Reader::from_str(xml);
        let mut d = Description {
            model_identifier: String::new(),
            guid: String::new(),
            variables: Vec::new(),
            start: 0.0,
            stop: 1.0,
            step: 1e-2,
            tolerance: 1e-6,
            model_exchange: false,
            states: 0,
        };
        let mut in_derivatives = false;
        loop {
            let event = reader
                .read_event()
                .map_err(|e| format!("modelDescription.xml: {e}"))?;
            let e = match &event {
                Event::Start(e) | Event::Empty(e) => e,
                Event::End(e) => {
                    if e.name().into_inner() == "Derivatives" {
                        in_derivatives = false;
                    }
                    continue;
                }
                Event::Eof => break,
                _ => continue,
            };
            let attr = |name: &str| -> Option<String> {
                e.attributes()
                    .flatten()
                    .find(|a| a.key.into_inner() == name)
                    .and_then(|a| {
                        a.normalized_value(XmlVersion::Explicit1_0)
                            .ok()
                            .map(|v| v.into_owned())
                    })
            };
            let number = |name: &str| attr(name).and_then(|v| v.parse::<f64>().ok());
            match e.name().into_inner() {
                "fmiModelDescription" => d.guid = attr("guid").unwrap_or_default(),
                "CoSimulation" => d.model_identifier = attr("modelIdentifier").unwrap_or_default(),
                "ModelExchange" => d.model_exchange = true,
                "Derivatives" => in_derivatives = matches!(event, Event::Start(_)),
                "Unknown" if in_derivatives => d.states += 1,
                "DefaultExperiment" => {
                    d.start = number("startTime").unwrap_or(d.start);
                    d.stop = number("stopTime").unwrap_or(d.stop);
                    d.step = number("stepSize").unwrap_or(d.step);
                    d.tolerance = number("tolerance").unwrap_or(d.tolerance);
                }
                "ScalarVariable" => d.variables.push(Variable {
                    name: attr("name").unwrap_or_default(),
                    vr: attr("valueReference")
                        .and_then(|v| v.parse().ok())
                        .ok_or("a ScalarVariable has no valueReference")?,
                    causality: attr("causality").unwrap_or_else(|| "local".into()),
                    variability: attr("variability").unwrap_or_else(|| "continuous".into()),
                    start: None,
                }),
                "Real" => {
                    if let Some(v) = d.variables.last_mut() {
                        v.start = number("start");
                    }
                }
                _ => {}
            }
        }
        if d.guid.is_empty() || d.model_identifier.is_empty() {
            return Err(
                "modelDescription.xml has no guid or no CoSimulation modelIdentifier".into(),
            );
        }
        Ok(d)
    }

    pub fn with_causality(&self, causality: &str) -> Vec<&Variable> {
        self.variables
            .iter()
            .filter(|v| v.causality == causality)
            .collect()
    }

    pub fn variable(&self, name: &str) -> Option<&Variable> {
        self.variables.iter().find(|v| v.name == name)
    }
}

/// Extracts `binaries/linux64/<id>.so` and `modelDescription.xml` from a `.fmu` into `dir`;
/// returns the paths of the binary and of the XML.
pub fn extract(fmu: &Path, dir: &Path) -> Result<(PathBuf, PathBuf), String> {
    let file =
        std::fs::File::open(fmu).map_err(|e| format!("cannot open {}: {e}", fmu.display()))?;
    let mut zip = zip::ZipArchive::new(file)
        .map_err(|e| format!("{} is not a zip archive: {e}", fmu.display()))?;
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let mut read = |name: &str| -> Result<Vec<u8>, String> {
        let mut entry = zip
            .by_name(name)
            .map_err(|e| format!("{} has no {name}: {e}", fmu.display()))?;
        let mut bytes = Vec::new();
        entry
            .read_to_end(&mut bytes)
            .map_err(|e| format!("cannot read {name} from {}: {e}", fmu.display()))?;
        Ok(bytes)
    };
    let xml = read("modelDescription.xml")?;
    let description = Description::parse(&String::from_utf8_lossy(&xml))?;
    let host = crate::platform::Platform::host().ok_or("no FMU binary for this machine")?;
    let so_name = format!(
        "binaries/{}/{}.{}",
        host.folder(crate::package::Version::Fmi2),
        description.model_identifier,
        host.extension()
    );
    let so = read(&so_name)?;
    let xml_path = dir.join("modelDescription.xml");
    let so_path = dir.join(format!("{}.so", description.model_identifier));
    for (path, bytes) in [(&xml_path, &xml), (&so_path, &so)] {
        std::fs::write(path, bytes).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    }
    Ok((so_path, xml_path))
}

type Counters = unsafe extern "C" fn(fmi2Component, *mut u64, usize) -> usize;
type Bench = unsafe extern "C" fn(fmi2Component, u32, u64, fmi2Real) -> fmi2Status;

/// The FMI functions the benchmark calls, resolved from the loaded library. The pointers
/// stay valid as long as the [`Binary`] holding them (and so the library) lives.
#[derive(Clone, Copy)]
pub struct Functions {
    /// The FMI 2.0 Co-Simulation functions.
    pub cs: CoSimulation,
    /// mechfmu's own (not FMI): work counters and the parts of a step alone. Absent in
    /// binaries built before they existed.
    counters: Option<Counters>,
    bench: Option<Bench>,
    /// The Model Exchange functions the benchmark calls, if the binary exports them all.
    pub me: Option<MeFunctions>,
}

/// The Model Exchange functions of [`Functions`].
#[derive(Clone, Copy)]
pub struct MeFunctions {
    new_discrete_states: NewDiscreteStates,
    enter_continuous_time_mode: Component,
    pub set_time: SetTime,
    pub set_continuous_states: SetStates,
    pub get_continuous_states: GetStates,
    pub get_derivatives: GetStates,
}

/// A loaded FMU binary and its description.
pub struct Binary {
    pub path: PathBuf,
    pub description: Description,
    pub functions: Functions,
    /// The FMI 3.0 side of the same binary (None: it exports no FMI 3.0 functions).
    pub fmi3: Option<super::fmu3::Api>,
    _library: libloading::Library,
}

impl Binary {
    /// Loads the `.so` at `so` and reads `xml` (the archive's modelDescription.xml).
    pub fn load(so: &Path, xml: &Path) -> Result<Binary, String> {
        let text = std::fs::read_to_string(xml)
            .map_err(|e| format!("cannot read {}: {e}", xml.display()))?;
        let description = Description::parse(&text)?;
        let library = fmi2_library::open(so)?;
        macro_rules! optional {
            ($name:literal) => {
                // SAFETY: mechfmu's own symbols, with the signatures of `export_fmu!`, and
                // FMI 2.0 functions, typed as the standard's header declares them.
                unsafe { library.get(concat!($name, "\0").as_bytes()) }
                    .ok()
                    .map(|s| *s)
            };
        }
        let functions = Functions {
            cs: CoSimulation::load(&library, so)?,
            counters: optional!("mechfmu_counters"),
            bench: optional!("mechfmu_bench"),
            me: (|| {
                Some(MeFunctions {
                    new_discrete_states: optional!("fmi2NewDiscreteStates")?,
                    enter_continuous_time_mode: optional!("fmi2EnterContinuousTimeMode")?,
                    set_time: optional!("fmi2SetTime")?,
                    set_continuous_states: optional!("fmi2SetContinuousStates")?,
                    get_continuous_states: optional!("fmi2GetContinuousStates")?,
                    get_derivatives: optional!("fmi2GetDerivatives")?,
                })
            })(),
        };
        let fmi3 = super::fmu3::Api::load(&library)?;
        Ok(Binary {
            path: so.to_path_buf(),
            description,
            functions,
            fmi3,
            _library: library,
        })
    }

    /// Whether the binary exports mechfmu's counters and `mechfmu_bench`.
    pub fn has_counters(&self) -> bool {
        self.functions.counters.is_some() && self.functions.bench.is_some()
    }
}

/// One instance of a loaded FMU.
pub struct Instance<'a> {
    pub binary: &'a Binary,
    pub component: fmi2Component,
    log: MessageLog,
}

impl<'a> Instance<'a> {
    /// A Co-Simulation instance.
    pub fn new(binary: &'a Binary) -> Result<Instance<'a>, String> {
        Self::instantiate(binary, fmi2CoSimulation)
    }

    /// A Model Exchange instance; `Err` if the binary has no Model Exchange functions.
    pub fn model_exchange(binary: &'a Binary) -> Result<Instance<'a>, String> {
        if binary.functions.me.is_none() {
            return Err(format!(
                "{} exports no Model Exchange functions",
                binary.path.display()
            ));
        }
        Self::instantiate(binary, fmi2ModelExchange)
    }

    fn instantiate(binary: &'a Binary, fmu_type: fmi2Type) -> Result<Instance<'a>, String> {
        let log = MessageLog::new();
        let d = &binary.description;
        let name = CString::new(d.model_identifier.as_str()).unwrap_or_default();
        let guid = CString::new(d.guid.as_str()).unwrap_or_default();
        // SAFETY: valid strings; callbacks and log outlive the instance (freed in Drop).
        let component = unsafe {
            (binary.functions.cs.instantiate)(
                name.as_ptr(),
                fmu_type,
                guid.as_ptr(),
                c"file:///tmp".as_ptr(),
                log.callbacks(),
                fmi2False,
                fmi2False,
            )
        };
        if component.is_null() {
            return Err(format!(
                "fmi2Instantiate of {} failed: {:?}",
                binary.path.display(),
                log.messages()
            ));
        }
        Ok(Instance {
            binary,
            component,
            log,
        })
    }

    fn check(&self, status: fmi2Status, what: &str) -> Result<(), String> {
        if status == fmi2OK {
            Ok(())
        } else {
            Err(format!(
                "{what} returned {status}: {}",
                self.messages().join("; ")
            ))
        }
    }

    /// The warnings and errors the FMU logged.
    pub fn messages(&self) -> Vec<String> {
        self.log
            .messages()
            .into_iter()
            .filter(|(status, _, _)| *status >= fmi2Warning)
            .map(|(_, _, text)| text)
            .collect()
    }

    /// `fmi2Reset` (unless fresh), `fmi2SetupExperiment(tol, start)`, start values,
    /// initialization: ready to step from `start`.
    pub fn start(
        &mut self,
        tolerance: f64,
        start: f64,
        values: &[(u32, f64)],
        reset: bool,
    ) -> Result<(), String> {
        let f = self.binary.functions.cs;
        // SAFETY: a live component of this binary; arrays of the stated lengths.
        unsafe {
            if reset {
                self.check((f.reset)(self.component), "fmi2Reset")?;
            }
            self.check(
                (f.setup_experiment)(self.component, fmi2True, tolerance, start, fmi2False, 0.0),
                "fmi2SetupExperiment",
            )?;
            self.check(
                (f.enter_initialization_mode)(self.component),
                "fmi2EnterInitializationMode",
            )?;
            for &(vr, value) in values {
                self.check((f.set_real)(self.component, &vr, 1, &value), "fmi2SetReal")?;
            }
            self.check(
                (f.exit_initialization_mode)(self.component),
                "fmi2ExitInitializationMode",
            )
        }
    }

    /// For a Model Exchange instance after [`Instance::start`] (in event mode): the event
    /// iteration (`fmi2NewDiscreteStates` until no new discrete states are needed), then
    /// `fmi2EnterContinuousTimeMode`.
    pub fn enter_continuous_time_mode(&mut self) -> Result<(), String> {
        let f = self.me()?;
        let mut info = fmi2EventInfo {
            newDiscreteStatesNeeded: fmi2True,
            ..fmi2EventInfo::default()
        };
        for _ in 0..100 {
            if info.newDiscreteStatesNeeded == fmi2False {
                break;
            }
            // SAFETY: a live component of this binary; `info` is writable.
            let status = unsafe { (f.new_discrete_states)(self.component, &mut info) };
            self.check(status, "fmi2NewDiscreteStates")?;
            if info.terminateSimulation != fmi2False {
                return Err("fmi2NewDiscreteStates: terminateSimulation at the start".into());
            }
        }
        // SAFETY: a live component of this binary.
        let status = unsafe { (f.enter_continuous_time_mode)(self.component) };
        self.check(status, "fmi2EnterContinuousTimeMode")
    }

    /// The Model Exchange functions (for an instance of [`Instance::model_exchange`]).
    pub fn me(&self) -> Result<MeFunctions, String> {
        self.binary
            .functions
            .me
            .ok_or_else(|| "the binary exports no Model Exchange functions".into())
    }

    /// `fmi2GetContinuousStates` into `x` (one value per state).
    pub fn continuous_states(&mut self, x: &mut [f64]) -> Result<(), String> {
        let f = self.me()?;
        // SAFETY: a live component; `x` has `x.len()` writable values.
        let status = unsafe { (f.get_continuous_states)(self.component, x.as_mut_ptr(), x.len()) };
        self.check(status, "fmi2GetContinuousStates")
    }

    #[inline]
    pub fn do_step(&mut self, t: f64, h: f64) -> fmi2Status {
        // SAFETY: a live component of this binary.
        unsafe { (self.binary.functions.cs.do_step)(self.component, t, h, fmi2True) }
    }

    #[inline]
    pub fn get_real(&mut self, vr: &[u32], out: &mut [f64]) -> fmi2Status {
        debug_assert_eq!(vr.len(), out.len());
        // SAFETY: a live component; arrays of the same length.
        unsafe {
            (self.binary.functions.cs.get_real)(
                self.component,
                vr.as_ptr(),
                vr.len(),
                out.as_mut_ptr(),
            )
        }
    }

    #[inline]
    pub fn set_real(&mut self, vr: &[u32], values: &[f64]) -> fmi2Status {
        debug_assert_eq!(vr.len(), values.len());
        // SAFETY: a live component; arrays of the same length.
        unsafe {
            (self.binary.functions.cs.set_real)(
                self.component,
                vr.as_ptr(),
                vr.len(),
                values.as_ptr(),
            )
        }
    }

    /// Cumulative (communication steps, accepted, rejected, model evaluations), if the
    /// binary exports them.
    pub fn counters(&self) -> Option<[u64; 4]> {
        let f = self.binary.functions.counters?;
        let mut out = [0u64; 4];
        // SAFETY: a live component; room for 4 counters.
        let n = unsafe { f(self.component, out.as_mut_ptr(), out.len()) };
        (n >= 4).then_some(out)
    }

    /// Repeats one part of a step `n` times on a copy of the instance (`mechfmu_bench`).
    pub fn bench(&mut self, part: Part, n: u64, h: f64) -> Result<(), String> {
        let f = self
            .binary
            .functions
            .bench
            .ok_or("the binary does not export mechfmu_bench (rebuild it)")?;
        // SAFETY: a live component.
        self.check(
            unsafe { f(self.component, part as u32, n, h) },
            "mechfmu_bench",
        )
    }
}

pub use mechfmu::simulation::Part;

impl Drop for Instance<'_> {
    fn drop(&mut self) {
        // SAFETY: live, freed once.
        unsafe { (self.binary.functions.cs.free_instance)(self.component) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_the_oscillator_description() {
        let xml = std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../modelDescription/Oscillator.xml"
        ))
        .unwrap();
        let d = Description::parse(&xml).unwrap();
        assert_eq!(d.model_identifier, "Oscillator");
        assert!(d.guid.starts_with('{'));
        assert_eq!(
            (d.start, d.stop, d.step, d.tolerance),
            (0.0, 20.0, 0.01, 1e-6)
        );
        let x = d.variable("x").unwrap();
        assert_eq!(
            (x.vr, x.causality.as_str(), x.start),
            (6, "output", Some(1.0))
        );
        assert_eq!(d.with_causality("input").len(), 1);
        assert_eq!(d.variable("x_ddot").unwrap().start, None);
    }
}
