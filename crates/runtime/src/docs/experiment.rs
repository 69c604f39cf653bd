//! The page's plot: the default experiment run on the mechanism's [`Simulation`] (the
//! steps `fmi2DoStep` takes), or, when that run stands still (an equilibrium, every curve
//! flat), the mechanism's [`MovingCase`] on the same simulation, with the reason in words.

use super::{escape, num, svg};
use crate::model::{Causality, Layout, Mechanism, MovingCase, SetPhase, Variable};
use crate::simulation::{Simulation, StepFailure};
use std::fmt::Write as _;

/// A run for the plot: times and the plotted variables' values.
#[derive(Clone, Debug, PartialEq)]
pub struct Trajectory {
    pub time: Vec<f64>,
    /// (variable, values at `time`), in value-reference order.
    pub signals: Vec<(&'static Variable, Vec<f64>)>,
    /// Why the run ended before the stop time, if it did.
    pub stopped: Option<String>,
}

impl Trajectory {
    /// Whether nothing moved: every plotted value equal, to the last bit, to its first.
    pub fn stands_still(&self) -> bool {
        self.time.len() > 1
            && self
                .signals
                .iter()
                .all(|(_, values)| values.iter().all(|v| v.to_bits() == values[0].to_bits()))
    }
}

/// Runs the default experiment of `M` on its simulation (start values as declared, inputs
/// at their start values, the steps `fmi2DoStep` takes) and records the states it outputs
/// (every output when it has no state) at every communication point.
pub fn default_experiment<M: Mechanism>() -> Result<Trajectory, String> {
    run::<M>(&[], M::EXPERIMENT.stop)
}

/// Runs `case` as the default experiment is run, with its values set before
/// initialization (inputs held at theirs), to its own stop time if it has one.
pub fn moving_case<M: Mechanism>(case: &MovingCase) -> Result<Trajectory, String> {
    run::<M>(case.values, case.stop.unwrap_or(M::EXPERIMENT.stop))
}

fn run<M: Mechanism>(values: &[(&str, f64)], stop: f64) -> Result<Trajectory, String> {
    let e = M::EXPERIMENT;
    let mut sim = Simulation::<M>::new(Layout::new(M::VARIABLES)?);
    for (name, value) in values {
        let vr = M::VARIABLES
            .iter()
            .position(|v| v.name == *name)
            .ok_or_else(|| format!("`{name}` names no variable"))?;
        sim.set_real(&[vr as u32], &[*value], SetPhase::Instantiated)?;
    }
    sim.setup(Some(e.tolerance), e.start)?;
    sim.update()
        .map_err(|m| format!("initialization failed: {m}"))?;
    let plotted = plotted::<M>();
    let vrs: Vec<u32> = plotted.iter().map(|(vr, _)| *vr).collect();
    let mut row = vec![0.0; vrs.len()];
    let mut time = Vec::new();
    let mut columns: Vec<Vec<f64>> = vec![Vec::new(); vrs.len()];
    let mut record = |sim: &mut Simulation<M>, t: f64| -> Result<(), String> {
        sim.get_real(&vrs, &mut row)?;
        time.push(t);
        for (c, v) in columns.iter_mut().zip(&row) {
            c.push(*v);
        }
        Ok(())
    };
    record(&mut sim, e.start)?;
    let mut stopped = None;
    let n = libm::round((stop - e.start) / e.step) as u64;
    for k in 0..n {
        let t = e.start + k as f64 * e.step;
        let h = (e.start + (k + 1) as f64 * e.step).min(stop) - t;
        match sim.step(t, h) {
            Ok(_) => record(&mut sim, t + h)?,
            Err(StepFailure::Rejected(message)) => return Err(message),
            Err(StepFailure::Stopped { time, message, .. }) => {
                stopped = Some(format!("stopped at t = {time}: {message}"));
                break;
            }
        }
    }
    Ok(Trajectory {
        time,
        signals: plotted.into_iter().map(|(_, v)| v).zip(columns).collect(),
        stopped,
    })
}

/// The states an importer sees (outputs with a derivative), every output if there are
/// none, with their value references.
fn plotted<M: Mechanism>() -> Vec<(u32, &'static Variable)> {
    let is_state = |v: &Variable| v.causality == Causality::Output && v.derivative.is_some();
    let any_state = M::VARIABLES.iter().any(is_state);
    M::VARIABLES
        .iter()
        .enumerate()
        .filter(|(_, v)| {
            if any_state {
                is_state(v)
            } else {
                v.causality == Causality::Output
            }
        })
        .map(|(i, v)| (i as u32, v))
        .collect()
}

/// The "Default experiment" section: the experiment, what the plot shows and the plot.
pub(super) fn section<M: Mechanism>() -> String {
    let e = M::EXPERIMENT;
    let mut h = String::new();
    let _ = writeln!(
        h,
        "<p>Start {} s, stop {} s, communication step {} s, relative tolerance {} \
         (the <code>DefaultExperiment</code>); every parameter, start value and input at its \
         default.</p>",
        num(e.start),
        num(e.stop),
        num(e.step),
        num(e.tolerance)
    );
    let run = match default_experiment::<M>() {
        Ok(run) => run,
        Err(e) => {
            let _ = writeln!(
                h,
                "<p class=\"warn\">The default experiment did not run: {}</p>",
                escape(&e)
            );
            return h;
        }
    };
    const RECORDED: &str = "The curves are this FMU's own states, recorded at every \
                            communication point.";
    let (run, label) = match (run.stands_still(), &M::MOVING_CASE) {
        (false, _) => {
            let _ = writeln!(h, "<p>{RECORDED}</p>");
            (Ok(run), "Outputs of the default experiment".to_string())
        }
        (true, None) => {
            let _ = writeln!(
                h,
                "<p>In the default experiment nothing moves: every state keeps its start \
                 value (an equilibrium of the mechanism under its default inputs), so the \
                 curves below are flat. Start a state or set an input away from this \
                 equilibrium to see the mechanism move. {RECORDED}</p>"
            );
            (Ok(run), "Outputs of the default experiment".to_string())
        }
        (true, Some(case)) => {
            let _ = writeln!(h, "<p>{} {RECORDED}</p>", why_the_case::<M>(case));
            let label = format!("Outputs of the case {}", case.name);
            (moving_case::<M>(case), label)
        }
    };
    match run {
        Ok(run) => {
            if let Some(why) = &run.stopped {
                let _ = writeln!(h, "<p class=\"warn\">The run {}</p>", escape(why));
            }
            h.push_str(&svg::plot(&run, &label));
        }
        Err(e) => {
            let _ = writeln!(
                h,
                "<p class=\"warn\">The case did not run: {}</p>",
                escape(&e)
            );
        }
    }
    h
}

/// Why the page plots `case`: the default experiment stands still, for the reason the
/// mechanism declares, and what the case shows and changes.
pub(super) fn why_the_case<M: Mechanism>(case: &MovingCase) -> String {
    format!(
        "In the default experiment {}; this is an equilibrium, so every state keeps its start \
         value. The plot below shows the case <code>{}</code> instead: {}. It differs from the \
         default experiment in {}{}.",
        escape(case.at_rest),
        escape(case.name),
        escape(case.shows),
        changed_values::<M>(case),
        case.stop.map_or(" only".to_string(), |t| format!(
            " and stops at {} s",
            num(t)
        )),
    )
}

/// "`phi` = 1.047 rad and `x_dot` = 0.2 m/s": the values a case sets, with their units.
fn changed_values<M: Mechanism>(case: &MovingCase) -> String {
    let values: Vec<String> = case
        .values
        .iter()
        .map(|(name, value)| {
            let unit = M::VARIABLES
                .iter()
                .find(|v| v.name == *name)
                .map_or("", |v| v.unit);
            let unit = if unit.is_empty() || unit == "1" {
                String::new()
            } else {
                format!(" {}", escape(unit))
            };
            format!("<code>{}</code> = {}{unit}", escape(name), num(*value))
        })
        .collect();
    match values.split_last() {
        None => "nothing".into(),
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} and {last}", rest.join(", ")),
    }
}
