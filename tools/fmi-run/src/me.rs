//! Model Exchange under the importers' one driver (`mechfmu_host::model_exchange`: fixed-step
//! RK4, state events located by bisection, the event iteration), for FMI 2.0 and FMI 3.0
//! instances of the `fmi` crate, each seen through [`MeInstance`]: the experiment's
//! communication steps, input events and recorded rows around it (see the crate's
//! documentation, "Model Exchange").

use crate::{Experiment, MeOptions, MeStats, Table, EVENT_LOCATION_TOLERANCE};
use mechfmu_host::model_exchange::{Crossing, Instance, Integration, Location, Options, Where};

pub(crate) use mechfmu_host::model_exchange::{CallNames, Event, Status};

/// The result of a call of the `fmi` crate, as the driver's [`Status`].
pub(crate) trait Outcome {
    fn status(self) -> Status;
}

impl Outcome for Status {
    fn status(self) -> Status {
        self
    }
}

impl Outcome for Result<fmi::fmi2::Fmi2Res, fmi::fmi2::Fmi2Error> {
    fn status(self) -> Status {
        use fmi::fmi2::{Fmi2Error as E, Fmi2Res as R};
        match self {
            Ok(R::OK) => Status::Ok,
            Ok(R::Warning) => Status::Warning("fmi2Warning"),
            Ok(R::Pending) => {
                Status::Fail("fmi2Pending (asynchronous steps are not supported)".into())
            }
            Err(E::Discard) => Status::Fail("fmi2Discard".into()),
            Err(E::Error) => Status::Fail("fmi2Error".into()),
            Err(E::Fatal) => Status::Fail("fmi2Fatal".into()),
            Err(e) => Status::Fail(e.to_string()),
        }
    }
}

impl Outcome for Result<fmi::fmi3::Fmi3Res, fmi::fmi3::Fmi3Error> {
    fn status(self) -> Status {
        use fmi::fmi3::{Fmi3Error as E, Fmi3Res as R};
        match self {
            Ok(R::OK) => Status::Ok,
            Ok(R::Warning) => Status::Warning("fmi3Warning"),
            Err(E::Discard) => Status::Fail("fmi3Discard".into()),
            Err(E::Error) => Status::Fail("fmi3Error".into()),
            Err(E::Fatal) => Status::Fail("fmi3Fatal".into()),
        }
    }
}

/// `Ok` for an OK status only; else an error naming the call (`call()`) and the status.
pub(crate) fn ok(call: impl FnOnce() -> String, outcome: impl Outcome) -> Result<(), String> {
    mechfmu_host::model_exchange::ok(call, outcome.status())
}

/// The event flags of the `fmi` crate, as the driver's [`Event`].
pub(crate) fn event(flags: &fmi::EventFlags) -> Event {
    Event {
        discrete_states_need_update: flags.discrete_states_need_update,
        terminate_simulation: flags.terminate_simulation,
        values_of_continuous_states_changed: flags.values_of_continuous_states_changed,
        next_event_time: flags.next_event_time,
    }
}

/// A Model Exchange instance, FMI 2.0 or 3.0, initialized and with the experiment's
/// variables resolved: what the driver calls, and the experiment's inputs and records.
pub(crate) trait MeInstance: Instance {
    /// The function that sets the inputs (`fmi2SetReal`, `fmi3SetFloat64`).
    const SET_INPUTS: &'static str;
    /// Sets the inputs to `row` (one value per input of the experiment).
    fn set_inputs(&mut self, row: &[f64]) -> Status;
    /// The inputs' names, for messages.
    fn input_list(&self) -> &str;
    /// One row of the result at `t`: `t`, then the recorded variables now.
    fn record(&mut self, t: f64) -> Result<Vec<f64>, String>;
}

/// An input event at the accepted point: `EnterEventMode`, the inputs `row` set in event
/// mode, the event iteration, `EnterContinuousTimeMode`, the states again if they changed,
/// the event indicators again.
fn input_event<I: MeInstance>(me: &mut Integration<I>, row: &[f64]) -> Result<(), String> {
    let what = "input event";
    me.enter_event_mode(what)?;
    let r = me.fmu.set_inputs(row);
    ok(
        || {
            format!(
                "{}({}) in event mode {}",
                I::SET_INPUTS,
                me.fmu.input_list(),
                me.at(me.t)
            )
        },
        r,
    )?;
    match me.finish_event(what)? {
        Some(stop) => Err(me.terminate_there(stop.why)),
        None => Ok(()),
    }
}

/// Integrates an instance just out of `ExitInitializationMode` (in event mode), with `nx`
/// states and `nz` event indicators, through the experiment: the initial event iteration,
/// then every communication step (input events, RK4 substeps, events), recording each
/// communication point; `Terminate` at the end. The FMU asking to stop ends the run with
/// `Terminate` and an error saying why.
pub(crate) fn integrate<I: MeInstance>(
    fmu: I,
    needs_completed_integrator_step: bool,
    sizes: (usize, usize),
    exp: &Experiment,
    options: &MeOptions,
) -> Result<(Table, MeStats), String> {
    let driver = Options {
        crossing: Crossing::Domain,
        location: Location::Time {
            tolerance: EVENT_LOCATION_TOLERANCE,
        },
        completed_integrator_step: needs_completed_integrator_step,
        warnings_pass: false,
    };
    let mut me = Integration::new(fmu, sizes, driver);
    // ExitInitializationMode left the FMU in event mode
    if let Some(stop) = me.finish_event("the initial event iteration")? {
        return Err(me.terminate_there(stop.why));
    }
    let r = me.fmu.get_continuous_states(&mut me.x);
    ok(
        || {
            format!(
                "{} at t = 0.0",
                Integration::<I>::call("GetContinuousStates")
            )
        },
        r,
    )?;

    let h = exp.step_size;
    let time = |k: usize| k as f64 * h;
    let mut rows = Vec::with_capacity(exp.steps + 1);
    rows.push(me.fmu.record(0.0)?);
    for k in 1..=exp.steps {
        me.at = Where::Step {
            step: k,
            steps: exp.steps,
            start: time(k - 1),
        };
        // the inputs of the step from t_{k-1}: row 0 was set in initialization mode; a
        // change is an input event at t_{k-1}
        if k > 1 && !exp.inputs.is_empty() {
            let (old, new) = (&exp.input_values[k - 2], &exp.input_values[k - 1]);
            if old.iter().zip(new).any(|(a, b)| a.to_bits() != b.to_bits()) {
                me.stats.input_events += 1;
                input_event(&mut me, new)?;
            }
        }
        let (t0, t1) = (time(k - 1), time(k));
        let m = options.substeps;
        for j in 1..=m {
            // the substeps' ends, the last exactly t_k
            let tj = if j == m {
                t1
            } else {
                t0 + (t1 - t0) * (j as f64 / m as f64)
            };
            if let Some(stop) = me.integrate_to(tj)? {
                return Err(me.terminate_there(stop.why));
            }
        }
        rows.push(me.fmu.record(t1)?);
    }
    let r = me.fmu.terminate();
    ok(|| Integration::<I>::call("Terminate"), r)?;
    Ok((
        Table {
            names: crate::column_names(exp),
            rows,
        },
        me.stats,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn statuses_are_named_by_version() {
        let warning = Ok::<_, fmi::fmi3::Fmi3Error>(fmi::fmi3::Fmi3Res::Warning).status();
        assert!(warning.is_ok());
        assert_eq!(
            ok(|| "fmi3DoStep".into(), warning),
            Err("fmi3DoStep returned fmi3Warning".into())
        );
        let discard = Err::<fmi::fmi2::Fmi2Res, _>(fmi::fmi2::Fmi2Error::Discard).status();
        assert!(!discard.is_ok());
        assert_eq!(
            ok(|| "fmi2DoStep".into(), discard),
            Err("fmi2DoStep returned fmi2Discard".into())
        );
    }
}
