//! `fmi3DoStep` beside `fmi2DoStep`: the same binary's FMI 3.0 Co-Simulation instance
//! ([`super::fmu3`]), started as the FMI 2.0 one is, its steps timed in the same runs and
//! counted by the same probe.
//!
//! One binary exports both standards' functions over the same simulation, so a
//! `fmi3DoStep` and a `fmi2DoStep` do the same work and differ by their FMI layer only (the
//! four out arguments of FMI 3.0, its state table). The instance is made by
//! `fmi3InstantiateCoSimulation` (no event mode, no early return, no intermediate
//! variables) with the `instantiationToken` of the FMI 3.0 modelDescription the binary
//! renders of itself, and started with `fmi3EnterInitializationMode(tolerance, start)` (no
//! stop time) and `fmi3ExitInitializationMode`, as
//! [`Instance::start`](super::fmu::Instance::start) starts the FMI 2.0 one; both keep the
//! FMU's start values. [`same_run`] checks that the two end a run with the same values, bit
//! for bit (the FMU's counters refuse an FMI 3.0 instance).
//!
//! Timing: [`super::native`] runs a configuration's `fmi3DoStep` loop right before or after
//! its `fmi2DoStep` loop (the order alternating), on the instance of the same turn and at
//! the same stack depth. Instructions: the probe [`probe`] (`--probe fmi3-step`), as the
//! `fmi2DoStep` one.

use super::clock::{cpu_ns, Stat};
use super::fmu::{self, Binary};
pub use super::fmu3::Instance;
use super::native::{self, Effort};
use super::report::Target;
use super::Figures;
use mechfmu::fmi3::ffi::fmi3Warning;

/// The target: `fmi3DoStep` within this fraction of `fmi2DoStep`.
pub const LIMIT: f64 = 0.05;

/// The timed loop of one run from a started instance: CPU ns of `n` steps of `h`.
pub fn step_loop(inst: &mut Instance, h: f64, n: usize) -> Result<f64, String> {
    let mut t = inst.binary.description.start;
    let t0 = cpu_ns();
    for _ in 0..n {
        let status = inst.do_step(t, h);
        if status > fmi3Warning {
            return Err(format!(
                "fmi3DoStep({t}, {h}) returned {status}: {}",
                inst.messages().join("; ")
            ));
        }
        t += h;
    }
    Ok((cpu_ns() - t0) as f64)
}

/// One run as [`native::step_run`]: (re)start untimed, then `n` timed steps; CPU ns.
pub fn step_run(
    inst: &mut Instance,
    tol: f64,
    h: f64,
    n: usize,
    fresh: bool,
) -> Result<f64, String> {
    inst.start(tol, inst.binary.description.start, !fresh)?;
    step_loop(inst, h, n)
}

/// Whether an FMI 2.0 and an FMI 3.0 instance that ran the same steps hold the same values,
/// bit for bit: the scalar `Float64` variables of the FMI 3.0 modelDescription that have the
/// same name and value reference in the FMI 2.0 one (every mechanism has some: its scalar
/// outputs).
pub fn same_run(two: &mut fmu::Instance, three: &mut Instance) -> Result<(), String> {
    let Some(api) = three.binary.fmi3.as_ref() else {
        return Ok(());
    };
    let d = &two.binary.description;
    let common: Vec<(&str, u32)> = (api.scalars.iter())
        .filter(|(name, vr)| d.variable(name).is_some_and(|v| v.vr == *vr))
        .map(|(name, vr)| (name.as_str(), *vr))
        .collect();
    let vrs: Vec<u32> = common.iter().map(|c| c.1).collect();
    let mut fmi2 = vec![0.0; vrs.len()];
    let status = two.get_real(&vrs, &mut fmi2);
    if status > mechfmu::fmi2::ffi::fmi2Warning {
        return Err(format!("fmi2GetReal returned {status}"));
    }
    let fmi3 = three.get_float64(&vrs)?;
    let differ: Vec<String> = (common.iter().zip(fmi2.iter().zip(&fmi3)))
        .filter(|(_, (a, b))| a.to_bits() != b.to_bits())
        .map(|((name, _), (a, b))| format!("{name} {a:e} (FMI 2.0) vs {b:e} (FMI 3.0)"))
        .collect();
    if differ.is_empty() {
        return Ok(());
    }
    Err(format!(
        "fmi3DoStep and fmi2DoStep ended the same run apart: {}",
        differ.join(", ")
    ))
}

/// The probe of `fmi3DoStep` under valgrind (`--probe fmi3-step`): a warm-up run, then
/// `repeat` runs, as the `fmi2DoStep` probe.
pub fn probe(
    binary: &Binary,
    h: f64,
    tol: f64,
    repeat: usize,
    max_steps: usize,
) -> Result<(), String> {
    let effort = Effort {
        runs: 1,
        max_steps,
        calls: 0,
    };
    let n = native::steps_per_run(binary, h, effort);
    let mut inst = Instance::new(binary)?;
    step_run(&mut inst, tol, h, n, true)?;
    for _ in 0..repeat {
        step_run(&mut inst, tol, h, n, false)?;
    }
    Ok(())
}

/// `fmi3DoStep` over `fmi2DoStep`, written as a signed percentage.
pub fn percent(ratio: f64) -> String {
    if ratio.is_finite() {
        format!("{:+.1} %", (ratio - 1.0) * 100.0)
    } else {
        "-".into()
    }
}

/// The target of one mechanism: judged on the instruction counts where they were counted
/// (repeatable), else on the median of its configurations' time ratios (the extremes of
/// four ratios on a busy machine are mostly noise; they are shown beside it).
pub fn target(m: &Figures) -> Option<Target> {
    let ratios: Vec<f64> = (m.steps.iter())
        .map(|s| s.fmi3_ratio())
        .filter(|r| r.is_finite())
        .collect();
    let time = Stat::of(&ratios);
    let counted = m.instructions.and_then(|c| c.fmi3_ratio());
    let mut value = Vec::new();
    if let Some(c) = counted {
        value.push(format!("instructions {} (h 1e-2, tol 1e-6)", percent(c)));
    }
    if time.runs > 0 {
        value.push(format!(
            "time {} (median of {} configurations; {} to {})",
            percent(time.median),
            time.runs,
            percent(time.min),
            percent(time.max)
        ));
    }
    let judged = counted.or((time.runs > 0).then_some(time.median))?;
    Some(Target {
        what: format!("{}: fmi3DoStep within 5 % of fmi2DoStep", m.name),
        limit: "≤ 5 % apart".into(),
        value: value.join("; "),
        met: Some((judged - 1.0).abs() <= LIMIT),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_difference_reads_both_ways() {
        assert_eq!(percent(1.031), "+3.1 %");
        assert_eq!(percent(0.98), "-2.0 %");
        assert_eq!(percent(f64::NAN), "-");
    }
}
