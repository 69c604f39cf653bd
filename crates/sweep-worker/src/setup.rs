//! The first request: the JSON setup every case of the sweep shares.

use crate::summary::Func;
use serde_json::{Map, Value};
use std::ffi::CString;
use std::path::PathBuf;

/// More communication points than this in one case is a setup error, not a long wait:
/// the loop would otherwise run (nearly) forever on a tiny or vanishing interval.
const MAX_POINTS: f64 = 1e9;

/// What every case shares.
#[derive(Debug)]
pub struct Setup {
    pub library: PathBuf,
    pub model_identifier: String,
    pub guid: CString,
    pub resource_location: CString,
    pub instance_name: CString,
    pub start_time: f64,
    pub stop_time: f64,
    pub output_interval: f64,
    pub tolerance: Option<f64>,
    pub set_stop_time: bool,
    pub can_vary_step: bool,
    /// The start values of a case come in this order.
    pub starts: Vec<Start>,
    /// The value references of the input table's columns after time.
    pub inputs: Vec<u32>,
    /// Read at every communication point.
    pub trajectory: Vec<u32>,
    /// Read once, after the last step.
    pub finals: Vec<u32>,
    pub summaries: Vec<Summary>,
    /// Optional (default false): the cases only step (the start values, initialization,
    /// `fmi2DoStep`s), without inputs, samples, final values or summaries (NaN): the FMU's
    /// own cost, which the Python side's benchmark compares the full cases with.
    pub bare: bool,
}

/// A variable a case sets before the simulation starts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Start {
    pub vr: u32,
    pub kind: StartKind,
    /// Set in initialization mode (after `fmi2EnterInitializationMode`) rather than before.
    pub initialization: bool,
}

/// The FMI type a start value is set with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StartKind {
    Real,
    Integer,
    Boolean,
}

/// One summary of a case: a function of a trajectory column, or a final value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Summary {
    pub func: Func,
    pub source: Source,
}

/// Where a summary's values come from: an index into `trajectory` or `finals`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    Trajectory(usize),
    Final(usize),
}

impl Setup {
    /// Parses and checks the setup request.
    pub fn parse(payload: &[u8]) -> Result<Setup, String> {
        Self::from_json(payload).map_err(|e| format!("setup: {e}"))
    }

    fn from_json(payload: &[u8]) -> Result<Setup, String> {
        let value: Value = serde_json::from_slice(payload).map_err(|e| format!("bad JSON: {e}"))?;
        let fields = Fields(value.as_object().ok_or("the JSON is not an object")?);
        let trajectory = fields.vrs("trajectory")?;
        let finals = fields.vrs("finals")?;
        let summaries = fields
            .array("summaries")?
            .iter()
            .enumerate()
            .map(|(i, s)| summary(s, trajectory.len(), finals.len()).map_err(|e| at(i, e)))
            .collect::<Result<_, _>>()?;
        let setup = Setup {
            library: PathBuf::from(fields.string("library")?),
            model_identifier: fields.string("model_identifier")?.to_string(),
            guid: fields.c_string("guid")?,
            resource_location: fields.c_string("resource_location")?,
            instance_name: fields.c_string("instance_name")?,
            start_time: fields.number("start_time")?,
            stop_time: fields.number("stop_time")?,
            output_interval: fields.number("output_interval")?,
            tolerance: fields.optional_number("tolerance")?,
            set_stop_time: fields.boolean("set_stop_time")?,
            can_vary_step: fields.boolean("can_vary_step")?,
            starts: fields
                .array("starts")?
                .iter()
                .enumerate()
                .map(|(i, s)| start(s).map_err(|e| at(i, e)))
                .collect::<Result<_, _>>()?,
            inputs: fields.vrs("inputs")?,
            trajectory,
            finals,
            summaries,
            bare: fields.optional_boolean("bare")?,
        };
        setup.check_times()?;
        Ok(setup)
    }

    /// Times the loop can finish with: finite, a positive interval, not too many points.
    fn check_times(&self) -> Result<(), String> {
        for (name, t) in [
            ("start_time", self.start_time),
            ("stop_time", self.stop_time),
            ("output_interval", self.output_interval),
        ] {
            if !t.is_finite() {
                return Err(format!("`{name}` is {t}"));
            }
        }
        // Finite times and a positive interval: never NaN.
        let points = (self.stop_time - self.start_time) / self.output_interval;
        if self.output_interval <= 0.0 || points > MAX_POINTS {
            return Err(format!(
                "output_interval {} from {} to {} makes {points:e} communication points \
                 (at most {MAX_POINTS:e})",
                self.output_interval, self.start_time, self.stop_time
            ));
        }
        Ok(())
    }

    /// The communication points of a case without input events, for the sample buffer.
    pub fn expected_points(&self) -> usize {
        let points = ((self.stop_time - self.start_time) / self.output_interval).ceil();
        points.clamp(0.0, MAX_POINTS) as usize + 2
    }
}

fn at(i: usize, e: String) -> String {
    format!("item {i} of {e}")
}

fn start(value: &Value) -> Result<Start, String> {
    let fields = Fields(value.as_object().ok_or("`starts`: not an object")?);
    let kind = match fields.string("type")? {
        "Real" => StartKind::Real,
        "Integer" => StartKind::Integer,
        "Boolean" => StartKind::Boolean,
        other => return Err(format!("`starts`: unknown type `{other}`")),
    };
    Ok(Start {
        vr: fields.vr("vr")?,
        kind,
        initialization: fields.boolean("initialization")?,
    })
}

fn summary(value: &Value, trajectory: usize, finals: usize) -> Result<Summary, String> {
    let fields = Fields(value.as_object().ok_or("`summaries`: not an object")?);
    let name = fields.string("func")?;
    let func = Func::parse(name).ok_or_else(|| format!("`summaries`: unknown func `{name}`"))?;
    let index = fields.index("index")?;
    let (source, len) = match fields.string("source")? {
        "trajectory" => (Source::Trajectory(index), trajectory),
        "final" => (Source::Final(index), finals),
        other => return Err(format!("`summaries`: unknown source `{other}`")),
    };
    if index >= len {
        return Err(format!(
            "`summaries`: index {index} is beyond the {len} value references of its source"
        ));
    }
    Ok(Summary { func, source })
}

/// The members of a JSON object, read with messages naming the one missing or mistyped.
struct Fields<'a>(&'a Map<String, Value>);

impl<'a> Fields<'a> {
    fn get(&self, name: &str) -> Result<&'a Value, String> {
        self.0.get(name).ok_or_else(|| format!("no `{name}`"))
    }

    fn typed<T>(
        &self,
        name: &str,
        what: &str,
        f: impl Fn(&'a Value) -> Option<T>,
    ) -> Result<T, String> {
        f(self.get(name)?).ok_or_else(|| format!("`{name}` is not {what}"))
    }

    fn string(&self, name: &str) -> Result<&'a str, String> {
        self.typed(name, "a string", Value::as_str)
    }

    fn c_string(&self, name: &str) -> Result<CString, String> {
        CString::new(self.string(name)?).map_err(|_| format!("`{name}` contains a NUL"))
    }

    fn number(&self, name: &str) -> Result<f64, String> {
        self.typed(name, "a number", Value::as_f64)
    }

    fn optional_number(&self, name: &str) -> Result<Option<f64>, String> {
        match self.get(name)? {
            Value::Null => Ok(None),
            _ => self.number(name).map(Some),
        }
    }

    fn boolean(&self, name: &str) -> Result<bool, String> {
        self.typed(name, "true or false", Value::as_bool)
    }

    /// False when absent.
    fn optional_boolean(&self, name: &str) -> Result<bool, String> {
        match self.0.get(name) {
            None => Ok(false),
            Some(_) => self.boolean(name),
        }
    }

    fn index(&self, name: &str) -> Result<usize, String> {
        self.typed(name, "an index", |v| {
            v.as_u64().and_then(|i| i.try_into().ok())
        })
    }

    fn vr(&self, name: &str) -> Result<u32, String> {
        self.typed(name, "a value reference", value_reference)
    }

    fn array(&self, name: &str) -> Result<&'a Vec<Value>, String> {
        self.typed(name, "an array", Value::as_array)
    }

    fn vrs(&self, name: &str) -> Result<Vec<u32>, String> {
        self.array(name)?
            .iter()
            .map(|v| {
                value_reference(v)
                    .ok_or_else(|| format!("`{name}` holds {v}, not a value reference"))
            })
            .collect()
    }
}

fn value_reference(value: &Value) -> Option<u32> {
    value.as_u64().and_then(|v| v.try_into().ok())
}

#[cfg(test)]
mod tests {
    use super::*;

    pub(crate) fn example() -> Value {
        serde_json::json!({
            "library": "/tmp/x/binaries/linux64/Oscillator.so",
            "model_identifier": "Oscillator",
            "guid": "{abc}",
            "resource_location": "file:///tmp/x/resources",
            "instance_name": "sweep-1",
            "start_time": 0.0, "stop_time": 10.0, "output_interval": 0.01,
            "tolerance": null, "set_stop_time": true, "can_vary_step": true,
            "starts": [{"vr": 0, "type": "Real", "initialization": false},
                       {"vr": 9, "type": "Boolean", "initialization": true}],
            "inputs": [5],
            "trajectory": [6, 7],
            "finals": [8],
            "summaries": [{"func": "max_abs", "source": "trajectory", "index": 1},
                          {"func": "final", "source": "final", "index": 0}]
        })
    }

    fn parse(value: &Value) -> Result<Setup, String> {
        Setup::parse(value.to_string().as_bytes())
    }

    #[test]
    fn parses_a_setup() {
        let setup = parse(&example()).unwrap();
        assert_eq!(setup.tolerance, None);
        assert_eq!(setup.starts[1].kind, StartKind::Boolean);
        assert!(setup.starts[1].initialization);
        assert_eq!(setup.summaries[0].source, Source::Trajectory(1));
        assert_eq!(setup.summaries[1].func, Func::Final);
        assert_eq!(setup.expected_points(), 1002);
        assert!(!setup.bare);
        let mut bare = example();
        bare["bare"] = true.into();
        assert!(parse(&bare).unwrap().bare);
    }

    fn refused(change: impl Fn(&mut Value)) -> String {
        let mut value = example();
        change(&mut value);
        parse(&value).unwrap_err()
    }

    #[test]
    fn refuses_what_it_cannot_run() {
        let message = refused(|v| v["summaries"][0]["func"] = "median".into());
        assert!(message.contains("unknown func `median`"), "{message}");
        let message = refused(|v| v["summaries"][1]["index"] = 1.into());
        assert!(message.contains("index 1 is beyond"), "{message}");
        let message = refused(|v| v["stop_time"] = "ten".into());
        assert!(message.contains("`stop_time` is not a number"), "{message}");
        let message = refused(|v| v["output_interval"] = 0.0.into());
        assert!(message.contains("communication points"), "{message}");
        let message = refused(|v| v["output_interval"] = 1e-12.into());
        assert!(message.contains("communication points"), "{message}");
        let message = refused(|v| v["inputs"][0] = (-1).into());
        assert!(message.contains("not a value reference"), "{message}");
        let message = refused(|v| v["starts"][0]["type"] = "String".into());
        assert!(message.contains("unknown type `String`"), "{message}");
        let message = refused(|v| v.as_object_mut().unwrap().remove("guid").map(drop).unwrap());
        assert!(message.contains("no `guid`"), "{message}");
        let message = Setup::parse(b"{\"library\": ").unwrap_err();
        assert!(message.contains("bad JSON"), "{message}");
    }
}
