//! FMU states (`fmi2GetFMUstate`, `fmi3GetFMUState` & co.) and their portable serialized
//! form, the same for both standards but for the token that names the build.
//!
//! Serialized layout (all integers and floats little-endian, floats as IEEE-754 bits):
//!
//! | field | type |
//! |---|---|
//! | magic `b"mechfmuS"` | 8 bytes |
//! | format version | u32 |
//! | model identifier, GUID (FMI 2.0) or instantiation token (FMI 3.0) | u32 length + UTF-8 bytes, each |
//! | values (every variable by value reference, then time) | u32 count + f64 each |
//! | inputs, then their 1st and 2nd derivatives | u32 count + f64 × 3 each |
//! | solver: next step size (u8 present + f64), log2 of the error memory (f64) | |
//! | tolerance: rtol, atol | f64, f64 |
//! | flags: 1 warning active, 2 values dirty, 4 terminated, 8 solver on its 8th-order method, 16 a Model Exchange instance's | u8 |
//! | state-machine state | u16 |
//! | stop time (u8 present + f64), last successful time (f64), last step status (u32) | |
//! | checksum: FNV-1a 64 of every byte before it | u64 |
//!
//! No pointers, no padding, no host-dependent sizes: a state serialized in one process (or
//! machine) restores in another running the same FMU.

use super::machine::{Interface, ModelState};
use super::Version;
use crate::model::Mechanism;
use crate::simulation::SavedState;
use crate::solver::{SolverMemory, Tolerance};

const MAGIC: &[u8; 8] = b"mechfmuS";
/// 2: the solver's method among the flags. 3: the solver's error memory as its logarithm.
/// 4: the interface type among the flags.
const FORMAT_VERSION: u32 = 4;
/// Marks live in-memory FMU states handed to the importer.
pub(crate) const STATE_MAGIC: u64 = 0x6d65_6368_7374_6174; // "mechstat"

/// Everything an FMU state captures.
#[derive(Clone, Debug, PartialEq)]
pub struct FmuState {
    pub(crate) magic: u64,
    /// The standard and the interface type of the instance it was saved from.
    pub version: Version,
    pub interface: Interface,
    pub sim: SavedState,
    pub model_state: ModelState,
    pub stop_time: Option<f64>,
    pub last_successful_time: f64,
    pub terminated: bool,
    pub last_step_status: super::Status,
}

/// The largest status either standard has (`fmi2Pending`).
const LAST_STATUS: u32 = 5;

fn fnv(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

/// Rewrites the checksum (the last 8 bytes) of serialized bytes to match the rest, so edited
/// bytes get past it to the fields behind (for fuzzing); fewer than 8 bytes are left alone.
pub fn reseal(bytes: &mut [u8]) {
    let Some(n) = bytes.len().checked_sub(8) else {
        return;
    };
    let checksum = fnv(&bytes[..n]);
    bytes[n..].copy_from_slice(&checksum.to_le_bytes());
}

impl FmuState {
    /// The serialized bytes of this state, for mechanism `M` (the token of the standard it
    /// was saved under).
    pub fn to_bytes<M: Mechanism>(&self) -> Vec<u8> {
        let mut w = Vec::with_capacity(256 + 8 * self.sim.values.len());
        w.extend_from_slice(MAGIC);
        w.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
        for s in [M::NAME.to_string(), self.version.token::<M>()] {
            w.extend_from_slice(&(s.len() as u32).to_le_bytes());
            w.extend_from_slice(s.as_bytes());
        }
        let f = |w: &mut Vec<u8>, x: f64| w.extend_from_slice(&x.to_bits().to_le_bytes());
        let opt = |w: &mut Vec<u8>, x: Option<f64>| {
            w.push(x.is_some() as u8);
            f(w, x.unwrap_or(0.0));
        };
        w.extend_from_slice(&(self.sim.values.len() as u32).to_le_bytes());
        self.sim.values.iter().for_each(|&x| f(&mut w, x));
        w.extend_from_slice(&(self.sim.inputs.len() as u32).to_le_bytes());
        self.sim.inputs.iter().for_each(|&x| f(&mut w, x));
        self.sim.input_derivatives.iter().for_each(|d| {
            f(&mut w, d[0]);
            f(&mut w, d[1]);
        });
        opt(&mut w, self.sim.solver.h_next);
        f(&mut w, self.sim.solver.log2_err_prev);
        f(&mut w, self.sim.tolerance.rtol());
        f(&mut w, self.sim.tolerance.atol());
        w.push(
            self.sim.warning_active as u8
                | (self.sim.dirty as u8) << 1
                | (self.terminated as u8) << 2
                | (self.sim.solver.high_order as u8) << 3
                | ((self.interface == Interface::ModelExchange) as u8) << 4,
        );
        w.extend_from_slice(&(self.model_state as u16).to_le_bytes());
        opt(&mut w, self.stop_time);
        f(&mut w, self.last_successful_time);
        w.extend_from_slice(&self.last_step_status.to_le_bytes());
        let checksum = fnv(&w);
        w.extend_from_slice(&checksum.to_le_bytes());
        w
    }

    /// Reads serialized bytes, refusing anything malformed, truncated, corrupted, of
    /// another format version, or of another model or standard than `version`'s `M`.
    pub fn from_bytes<M: Mechanism>(bytes: &[u8], version: Version) -> Result<FmuState, String> {
        let mut r = Reader::open(bytes)?;
        check_origin::<M>(&mut r, version)?;
        let values = read_values::<M>(&mut r)?;
        let (inputs, input_derivatives) = read_inputs::<M>(&mut r)?;
        let (solver, tolerance, flags) = read_solver(&mut r)?;
        let model_state = read_model_state(&mut r)?;
        let stop_time = r.opt_f64()?;
        let last_successful_time = r.f64()?;
        let last_step_status = r.u32()?;
        if last_step_status > LAST_STATUS {
            return Err(format!(
                "serialized FMU state has an unknown step status {last_step_status}"
            ));
        }
        let interface = if flags & 16 != 0 {
            Interface::ModelExchange
        } else {
            Interface::CoSimulation
        };
        check_reachable(model_state, interface, version)?;
        let time = values[values.len() - 1];
        if values
            .iter()
            .chain(&inputs)
            .chain(input_derivatives.iter().flatten())
            .any(|x| x.is_nan())
            || !time.is_finite()
            || !last_successful_time.is_finite()
            || stop_time.is_some_and(|s| !s.is_finite())
        {
            return Err("serialized FMU state has values that are not numbers".into());
        }
        r.finish()?;
        Ok(FmuState {
            magic: STATE_MAGIC,
            version,
            interface,
            sim: SavedState {
                values,
                inputs,
                input_derivatives,
                solver,
                tolerance,
                warning_active: flags & 1 != 0,
                dirty: flags & 2 != 0,
            },
            model_state,
            stop_time,
            last_successful_time,
            terminated: flags & 4 != 0,
            last_step_status,
        })
    }
}

/// Refuses the state of another model, or of another build or standard of this one (the
/// model identifier, then the GUID or instantiation token of `version`).
fn check_origin<M: Mechanism>(r: &mut Reader, version: Version) -> Result<(), String> {
    let name = r.string()?;
    let guid = r.string()?;
    if name != M::NAME {
        return Err(format!(
            "serialized FMU state is of model `{name}`, not `{}`",
            M::NAME
        ));
    }
    let expected = version.token::<M>();
    if guid != expected {
        let what = match version {
            Version::Fmi2 => "GUID",
            Version::Fmi3 => "instantiation token",
        };
        return Err(format!(
            "serialized FMU state is of another build of {name}, or of its other FMI version ({what} {guid}, this FMU has {expected})"
        ));
    }
    Ok(())
}

/// The values: one per variable of `M`, then the time.
fn read_values<M: Mechanism>(r: &mut Reader) -> Result<Vec<f64>, String> {
    let n = r.u32()? as usize;
    if n != M::VARIABLES.len() + 1 {
        return Err(format!(
            "serialized FMU state has {n} values; {} has {}",
            M::NAME,
            M::VARIABLES.len() + 1
        ));
    }
    (0..n).map(|_| r.f64()).collect()
}

/// The inputs at the communication point, then their first and second derivatives.
fn read_inputs<M: Mechanism>(r: &mut Reader) -> Result<(Vec<f64>, Vec<[f64; 2]>), String> {
    let n_inputs = r.u32()? as usize;
    if n_inputs > M::VARIABLES.len() {
        return Err(format!("serialized FMU state claims {n_inputs} inputs"));
    }
    let inputs = (0..n_inputs)
        .map(|_| r.f64())
        .collect::<Result<Vec<_>, _>>()?;
    let input_derivatives = (0..n_inputs)
        .map(|_| Ok([r.f64()?, r.f64()?]))
        .collect::<Result<Vec<_>, String>>()?;
    Ok((inputs, input_derivatives))
}

/// The solver's memory and tolerance, and the flags (the solver's method among them),
/// refused unless the solver can have them.
fn read_solver(r: &mut Reader) -> Result<(SolverMemory, Tolerance, u8), String> {
    let h_next = r.opt_f64()?;
    let log2_err_prev = r.f64()?;
    let (rtol, atol) = (r.f64()?, r.f64()?);
    if ![rtol, atol].iter().all(|x| x.is_finite() && *x > 0.0) {
        return Err("serialized FMU state has an invalid tolerance".into());
    }
    let tolerance =
        Tolerance::new(rtol, atol).ok_or("serialized FMU state has an invalid tolerance")?;
    let flags = r.u8()?;
    if flags & !31 != 0 {
        return Err(format!("serialized FMU state has unknown flags {flags:#x}"));
    }
    let solver = SolverMemory {
        h_next,
        log2_err_prev,
        high_order: flags & 8 != 0,
    };
    if !solver.is_valid() {
        return Err(format!(
            "serialized FMU state has a solver memory the solver cannot have \
             (next step size {h_next:?}, log2 of the error memory {log2_err_prev})"
        ));
    }
    Ok((solver, tolerance, flags))
}

/// The state-machine state, one of the standards' states.
fn read_model_state(r: &mut Reader) -> Result<ModelState, String> {
    let state_bits = r.u16()?;
    ModelState::ALL
        .into_iter()
        .find(|s| *s as u16 == state_bits)
        .ok_or_else(|| format!("serialized FMU state has an unknown instance state {state_bits}"))
}

/// Refuses a state-machine state no saved state of this runtime has. A forged state (valid
/// checksum, impossible content) would otherwise put the instance where it cannot leave
/// (Fatal, step in progress: not even fmi2FreeInstance is allowed) or return NaN with
/// fmi2OK.
fn check_reachable(
    model_state: ModelState,
    interface: Interface,
    version: Version,
) -> Result<(), String> {
    if matches!(
        model_state,
        ModelState::StepInProgress | ModelState::StepCanceled | ModelState::Fatal
    ) {
        return Err(format!(
            "serialized FMU state has instance state \"{}\", which no saved state of this FMU has",
            model_state.name()
        ));
    }
    let machine_of_other_interface = match model_state {
        ModelState::ContinuousTimeMode => interface != Interface::ModelExchange,
        ModelState::StepComplete | ModelState::StepFailed => interface != Interface::CoSimulation,
        // Co-Simulation has an event mode in FMI 3.0 only.
        ModelState::EventMode => interface == Interface::CoSimulation && version == Version::Fmi2,
        _ => false,
    };
    if machine_of_other_interface {
        return Err(format!(
            "serialized FMU state has instance state \"{}\", which a {} instance does not have",
            model_state.name(),
            interface.name()
        ));
    }
    Ok(())
}

/// A cursor over serialized bytes that refuses to read past the end.
struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    /// A reader of the fields after the magic tag and the format version, once both and the
    /// checksum check out.
    fn open(bytes: &'a [u8]) -> Result<Self, String> {
        if bytes.len() < MAGIC.len() + 4 + 8 || &bytes[..8] != MAGIC {
            return Err(
                "these bytes are not a serialized mechfmu FMU state (wrong magic tag)".into(),
            );
        }
        let (body, tail) = bytes.split_at(bytes.len() - 8);
        let mut r = Reader {
            bytes: &body[8..],
            at: 8,
        };
        let format = r.u32()?;
        if format != FORMAT_VERSION {
            return Err(format!(
                "serialized FMU state has format version {format}; this FMU reads version {FORMAT_VERSION}"
            ));
        }
        let checksum = u64::from_le_bytes(tail.try_into().expect("8 bytes"));
        if checksum != fnv(body) {
            return Err(
                "serialized FMU state is corrupted or truncated (checksum mismatch)".into(),
            );
        }
        Ok(r)
    }

    /// Refuses bytes left after the last field (before the checksum).
    fn finish(&self) -> Result<(), String> {
        let trailing = 8 + self.bytes.len() - self.at;
        if trailing != 0 {
            return Err(format!(
                "serialized FMU state has {trailing} unexpected trailing bytes"
            ));
        }
        Ok(())
    }

    fn take(&mut self, n: usize) -> Result<&[u8], String> {
        let start = self.at - 8;
        let end = start
            .checked_add(n)
            .filter(|&e| e <= self.bytes.len())
            .ok_or_else(|| {
                format!(
                    "serialized FMU state is truncated (needs {n} more bytes at offset {})",
                    self.at
                )
            })?;
        self.at += n;
        Ok(&self.bytes[start..end])
    }
    fn u8(&mut self) -> Result<u8, String> {
        Ok(self.take(1)?[0])
    }
    fn u16(&mut self) -> Result<u16, String> {
        Ok(u16::from_le_bytes(
            self.take(2)?.try_into().expect("2 bytes"),
        ))
    }
    fn u32(&mut self) -> Result<u32, String> {
        Ok(u32::from_le_bytes(
            self.take(4)?.try_into().expect("4 bytes"),
        ))
    }
    fn f64(&mut self) -> Result<f64, String> {
        Ok(f64::from_bits(u64::from_le_bytes(
            self.take(8)?.try_into().expect("8 bytes"),
        )))
    }
    fn opt_f64(&mut self) -> Result<Option<f64>, String> {
        let present = self.u8()?;
        let x = self.f64()?;
        match present {
            0 => Ok(None),
            1 => Ok(Some(x)),
            other => Err(format!(
                "serialized FMU state has an invalid option tag {other}"
            )),
        }
    }
    fn string(&mut self) -> Result<String, String> {
        let n = self.u32()? as usize;
        if n > 4096 {
            return Err(format!(
                "serialized FMU state has an implausible string length {n}"
            ));
        }
        String::from_utf8(self.take(n)?.to_vec())
            .map_err(|_| "serialized FMU state has a non-UTF-8 name".into())
    }
}

#[cfg(test)]
mod tests {
    use super::{fnv, reseal};

    #[test]
    fn reseal_writes_the_checksum_of_what_precedes_it() {
        let mut bytes: Vec<u8> = (0..24).collect();
        reseal(&mut bytes);
        assert_eq!(bytes[16..], fnv(&bytes[..16]).to_le_bytes());
        assert_eq!(bytes[..16], (0..16).collect::<Vec<u8>>()[..]);
        let mut short = [1u8, 2, 3];
        reseal(&mut short);
        assert_eq!(short, [1, 2, 3]);
    }
}
