//! A built FMU's FMI 3.0 side, loaded as [`super::fmu`] loads its FMI 2.0 side: the FMI 3.0
//! Co-Simulation functions of the same `.so` by their C names, the `instantiationToken`
//! and scalar `Float64` variables of the FMI 3.0 modelDescription the binary renders of
//! itself (`mechfmu_model_description_fmi3`), and an instance made and started as an
//! importer makes and starts one.

use super::fmu::Binary;
use mechfmu::fmi3::ffi::*;
use quick_xml::events::Event;
use quick_xml::{Reader, XmlVersion};
use std::ffi::{c_void, CStr, CString};
use std::sync::Mutex;

type Instantiate = unsafe extern "C" fn(
    fmi3String,
    fmi3String,
    fmi3String,
    fmi3Boolean,
    fmi3Boolean,
    fmi3Boolean,
    fmi3Boolean,
    *const fmi3ValueReference,
    usize,
    fmi3InstanceEnvironment,
    fmi3LogMessageCallback,
    fmi3IntermediateUpdateCallback,
) -> fmi3Instance;
type FreeInstance = unsafe extern "C" fn(fmi3Instance);
type EnterInitializationMode = unsafe extern "C" fn(
    fmi3Instance,
    fmi3Boolean,
    fmi3Float64,
    fmi3Float64,
    fmi3Boolean,
    fmi3Float64,
) -> fmi3Status;
type Call = unsafe extern "C" fn(fmi3Instance) -> fmi3Status;
type GetFloat64 = unsafe extern "C" fn(
    fmi3Instance,
    *const fmi3ValueReference,
    usize,
    *mut fmi3Float64,
    usize,
) -> fmi3Status;
/// `fmi3DoStep`.
pub type DoStep = unsafe extern "C" fn(
    fmi3Instance,
    fmi3Float64,
    fmi3Float64,
    fmi3Boolean,
    *mut fmi3Boolean,
    *mut fmi3Boolean,
    *mut fmi3Boolean,
    *mut fmi3Float64,
) -> fmi3Status;
type Render = unsafe extern "C" fn(*mut u8, usize) -> usize;

/// The FMI 3.0 functions the benchmark calls, from the library of a [`Binary`] (valid as
/// long as it lives).
#[derive(Clone, Copy)]
pub struct Functions {
    instantiate: Instantiate,
    free_instance: FreeInstance,
    enter_initialization_mode: EnterInitializationMode,
    exit_initialization_mode: Call,
    reset: Call,
    get_float64: GetFloat64,
    pub do_step: DoStep,
}

/// A binary's FMI 3.0 side: its functions, its instantiation token and the scalar
/// `Float64` variables of its FMI 3.0 modelDescription (name, value reference).
pub struct Api {
    pub functions: Functions,
    pub token: String,
    pub scalars: Vec<(String, u32)>,
}

impl Api {
    /// The FMI 3.0 side of `library`; None where it exports no FMI 3.0 functions or no
    /// `mechfmu_model_description_fmi3` (a binary built before them).
    pub fn load(library: &libloading::Library) -> Result<Option<Api>, String> {
        macro_rules! get {
            ($name:literal) => {
                // SAFETY: the symbols of `export_fmu!`, with the FMI 3.0 headers' signatures.
                match unsafe { library.get(concat!($name, "\0").as_bytes()) } {
                    Ok(symbol) => *symbol,
                    Err(_) => return Ok(None),
                }
            };
        }
        let functions = Functions {
            instantiate: get!("fmi3InstantiateCoSimulation"),
            free_instance: get!("fmi3FreeInstance"),
            enter_initialization_mode: get!("fmi3EnterInitializationMode"),
            exit_initialization_mode: get!("fmi3ExitInitializationMode"),
            reset: get!("fmi3Reset"),
            get_float64: get!("fmi3GetFloat64"),
            do_step: get!("fmi3DoStep"),
        };
        let render: Render = get!("mechfmu_model_description_fmi3");
        // SAFETY: `write_text`'s protocol: NULL asks for the length, then a buffer with room
        // for the text and its NUL.
        let xml = unsafe {
            let len = render(std::ptr::null_mut(), 0);
            let mut buf = vec![0u8; len + 1];
            let written = render(buf.as_mut_ptr(), buf.len());
            buf.truncate(written.min(len));
            String::from_utf8_lossy(&buf).into_owned()
        };
        if let Some(message) = xml.strip_prefix("error: ") {
            return Err(format!("the FMI 3.0 modelDescription: {message}"));
        }
        let (token, scalars) = parse(&xml)?;
        Ok(Some(Api {
            functions,
            token,
            scalars,
        }))
    }
}

/// The `instantiationToken` and the scalar `Float64` variables of an FMI 3.0
/// modelDescription (an array has `Dimension` children, so a start tag, not an empty one).
fn parse(xml: &str) -> Result<(String, Vec<(String, u32)>), String> {
    let mut reader = Reader::from_str(xml);
    let (mut token, mut scalars) = (None, Vec::new());
    loop {
        let event = reader
            .read_event()
            .map_err(|e| format!("FMI 3.0 modelDescription: {e}"))?;
        let (e, empty) = match &event {
            Event::Start(e) => (e, false),
            Event::Empty(e) => (e, true),
            Event::Eof => break,
            _ => continue,
        };
        let attr = |name: &str| {
            e.attributes()
                .flatten()
                .find(|a| a.key.into_inner() == name)
                .and_then(|a| a.normalized_value(XmlVersion::Explicit1_0).ok())
                .map(|v| v.into_owned())
        };
        match e.name().into_inner() {
            "fmiModelDescription" => token = attr("instantiationToken"),
            "Float64" if empty => {
                if let (Some(name), Some(vr)) = (attr("name"), attr("valueReference")) {
                    scalars.push((name, vr.parse().map_err(|_| "bad valueReference")?));
                }
            }
            _ => {}
        }
    }
    let token = token.ok_or("the FMI 3.0 modelDescription has no instantiationToken")?;
    Ok((token, scalars))
}

/// The warnings and errors an instance logged (its `instanceEnvironment`).
#[derive(Default)]
struct Log(Mutex<Vec<String>>);

unsafe extern "C" fn log_message(
    environment: fmi3InstanceEnvironment,
    status: fmi3Status,
    _category: fmi3String,
    message: fmi3String,
) {
    if environment.is_null() || message.is_null() || status < fmi3Warning {
        return;
    }
    // SAFETY: the environment is the instance's boxed `Log` (it outlives the instance); the
    // message a NUL-terminated string.
    let (log, text) = unsafe { (&*(environment as *const Log), CStr::from_ptr(message)) };
    if let Ok(mut messages) = log.0.lock() {
        messages.push(text.to_string_lossy().into_owned());
    }
}

/// The out arguments of `fmi3DoStep`: eventHandlingNeeded, terminateSimulation,
/// earlyReturn, lastSuccessfulTime.
#[derive(Default)]
struct Outs(bool, bool, bool, f64);

/// An FMI 3.0 Co-Simulation instance of a loaded binary.
pub struct Instance<'a> {
    pub binary: &'a Binary,
    f: Functions,
    instance: fmi3Instance,
    /// Where `fmi3DoStep` writes its out arguments (every call writes them all, so the
    /// loop does not reset them: what an importer's loop does per call is passing them).
    outs: Outs,
    log: Box<Log>,
}

impl<'a> Instance<'a> {
    pub fn new(binary: &'a Binary) -> Result<Instance<'a>, String> {
        let api = binary
            .fmi3
            .as_ref()
            .ok_or_else(|| format!("{} exports no FMI 3.0 functions", binary.path.display()))?;
        let name = CString::new(binary.description.model_identifier.as_str()).unwrap_or_default();
        let token = CString::new(api.token.as_str()).unwrap_or_default();
        let log = Box::<Log>::default();
        let environment = &*log as *const Log as *mut c_void;
        // SAFETY: valid strings; the log outlives the instance (freed first, in Drop).
        let instance = unsafe {
            (api.functions.instantiate)(
                name.as_ptr(),
                token.as_ptr(),
                c"/tmp/".as_ptr(),
                fmi3False,
                fmi3False,
                fmi3False,
                fmi3False,
                std::ptr::null(),
                0,
                environment,
                Some(log_message),
                None,
            )
        };
        let inst = Instance {
            binary,
            f: api.functions,
            instance,
            outs: Outs::default(),
            log,
        };
        if instance.is_null() {
            return Err(format!(
                "fmi3InstantiateCoSimulation of {} failed: {}",
                binary.path.display(),
                inst.messages().join("; ")
            ));
        }
        Ok(inst)
    }

    pub fn messages(&self) -> Vec<String> {
        self.log.0.lock().map(|m| m.clone()).unwrap_or_default()
    }

    fn check(&self, status: fmi3Status, what: &str) -> Result<(), String> {
        if status == fmi3OK {
            return Ok(());
        }
        Err(format!(
            "{what} returned {status}: {}",
            self.messages().join("; ")
        ))
    }

    /// `fmi3Reset` (unless fresh), `fmi3EnterInitializationMode(tolerance, start)` without a
    /// stop time, `fmi3ExitInitializationMode`: in step mode at `start`.
    pub fn start(&mut self, tolerance: f64, start: f64, reset: bool) -> Result<(), String> {
        let (f, i) = (self.f, self.instance);
        // SAFETY: a live instance of this binary.
        unsafe {
            if reset {
                self.check((f.reset)(i), "fmi3Reset")?;
            }
            let status = (f.enter_initialization_mode)(i, true, tolerance, start, false, 0.0);
            self.check(status, "fmi3EnterInitializationMode")?;
            self.check(
                (f.exit_initialization_mode)(i),
                "fmi3ExitInitializationMode",
            )
        }
    }

    #[inline]
    pub fn do_step(&mut self, t: f64, h: f64) -> fmi3Status {
        let o = &mut self.outs;
        // SAFETY: a live instance; the out arguments are writable fields.
        unsafe {
            (self.f.do_step)(
                self.instance,
                t,
                h,
                true,
                &mut o.0,
                &mut o.1,
                &mut o.2,
                &mut o.3,
            )
        }
    }

    /// `fmi3GetFloat64` of the value references `vrs`.
    pub fn get_float64(&mut self, vrs: &[u32]) -> Result<Vec<f64>, String> {
        let mut out = vec![0.0; vrs.len()];
        // SAFETY: a live instance; arrays of the stated lengths.
        let status = unsafe {
            (self.f.get_float64)(
                self.instance,
                vrs.as_ptr(),
                vrs.len(),
                out.as_mut_ptr(),
                out.len(),
            )
        };
        self.check(status, "fmi3GetFloat64").map(|_| out)
    }
}

impl Drop for Instance<'_> {
    fn drop(&mut self) {
        if !self.instance.is_null() {
            // SAFETY: live, freed once, before its log.
            unsafe { (self.f.free_instance)(self.instance) }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_the_token_and_the_scalars_of_the_fmi3_description() {
        let xml = std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../modelDescription/fmi3/RigidBody.xml"
        ))
        .unwrap();
        let (token, scalars) = parse(&xml).unwrap();
        assert!(token.starts_with('{'));
        let find = |n: &str| scalars.iter().find(|s| s.0 == n).map(|s| s.1);
        assert_eq!(find("M"), Some(0));
        assert_eq!(find("E_kin"), Some(25));
        assert_eq!(find("w"), None, "an array is not a scalar");
    }
}
