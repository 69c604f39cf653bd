//! An importer's fixed-step Model Exchange integrator, over an instance of either
//! standard ([`ModelExchangeInstance`]): the importers' one driver
//! (`mechfmu_host::model_exchange`), one step of the grid t0 + n·h at a time.

use crate::ffi::{Status, OK, WARNING};
use crate::importer::ModelExchangeInstance;
use mechfmu_host::model_exchange::{self as driver, CallNames, Crossing, Event, Integration};
use mechfmu_host::model_exchange::{Location, Options, Where};

/// An importer's Model Exchange integrator, of either standard: fixed-step classical
/// Runge-Kutta (RK4) through SetTime, SetContinuousStates and GetDerivatives
/// (fmi3GetContinuousStateDerivatives), the time of step n computed as t0 + n·h; after each
/// step its event indicators, a change of domain of one located by bisection (the step
/// cut short there, the rest of it following the event), CompletedIntegratorStep, and an
/// event (EnterEventMode, the event iteration of fmi2NewDiscreteStates or
/// fmi3UpdateDiscreteStates, EnterContinuousTimeMode) at a state event or where the FMU
/// asks for one.
pub struct MeIntegrator {
    pub t0: f64,
    pub h: f64,
    /// Steps done.
    pub n: u64,
    /// The continuous states.
    pub x: Vec<f64>,
    /// The event indicators at the last accepted point.
    pub z: Vec<f64>,
    /// Events handled (after initialization's).
    pub events: u64,
    /// The FMU said terminateSimulation.
    pub terminated: bool,
    /// FMI calls made.
    pub calls: u64,
}

/// How this importer drives Model Exchange: a state event is a change of domain (the
/// standard's definition), located to 1e-12 s; a Warning lets the run go on.
const OPTIONS: Options = Options {
    crossing: Crossing::Domain,
    location: Location::Time { tolerance: 1e-12 },
    completed_integrator_step: true,
    warnings_pass: true,
};

/// An instance as the driver sees it, counting the calls made and the events entered.
struct Counted<'a, T> {
    inst: &'a mut T,
    calls: u64,
    events: u64,
}

/// A status (the same numbers in both standards) as the driver's, named in the instance's
/// standard.
fn status<T: ModelExchangeInstance>(s: Status) -> driver::Status {
    let fmi2 = T::NAMES.prefix == "fmi2";
    match s {
        OK => driver::Status::Ok,
        WARNING if fmi2 => driver::Status::Warning("fmi2Warning"),
        WARNING => driver::Status::Warning("fmi3Warning"),
        s if fmi2 => driver::Status::Fail(crate::ffi::status_name(s)),
        s => driver::Status::Fail(crate::ffi3::status_name(s)),
    }
}

impl<T: ModelExchangeInstance> driver::Instance for Counted<'_, T> {
    const NAMES: CallNames = T::NAMES;

    fn set_time(&mut self, t: f64) -> driver::Status {
        self.calls += 1;
        status::<T>(self.inst.set_time(t))
    }

    fn set_continuous_states(&mut self, x: &[f64]) -> driver::Status {
        self.calls += 1;
        status::<T>(self.inst.set_continuous_states(x))
    }

    fn get_derivatives(&mut self, dx: &mut [f64]) -> driver::Status {
        self.calls += 1;
        status::<T>(self.inst.get_derivatives(dx))
    }

    fn get_event_indicators(&mut self, z: &mut [f64]) -> driver::Status {
        self.calls += 1;
        status::<T>(self.inst.get_event_indicators(z))
    }

    fn completed_integrator_step(
        &mut self,
        enter: &mut bool,
        terminate: &mut bool,
    ) -> driver::Status {
        self.calls += 1;
        let (s, e, t) = self.inst.completed_integrator_step(true);
        (*enter, *terminate) = (e, t);
        status::<T>(s)
    }

    fn enter_event_mode(&mut self) -> driver::Status {
        self.calls += 1;
        self.events += 1;
        status::<T>(self.inst.enter_event_mode())
    }

    fn update_discrete_states(&mut self, event: &mut Event) -> driver::Status {
        self.calls += 1;
        let (s, e) = self.inst.update_discrete_states();
        *event = e;
        status::<T>(s)
    }

    fn enter_continuous_time_mode(&mut self) -> driver::Status {
        self.calls += 1;
        status::<T>(self.inst.enter_continuous_time_mode())
    }

    fn get_continuous_states(&mut self, x: &mut [f64]) -> driver::Status {
        self.calls += 1;
        status::<T>(self.inst.get_continuous_states(x))
    }

    /// Not called: the scenarios end their instances themselves, and the driver
    /// terminates only when asked to after a stop.
    fn terminate(&mut self) -> driver::Status {
        driver::Status::Ok
    }
}

impl MeIntegrator {
    /// Takes over an initialized Model Exchange instance (in event mode): the event
    /// iteration at the start, continuous-time mode, the states and indicators.
    pub fn start<T: ModelExchangeInstance>(inst: &mut T, h: f64) -> Result<MeIntegrator, String> {
        let (nx, ni) = inst.counts();
        let mut me = MeIntegrator {
            t0: inst.start_time(),
            h,
            n: 0,
            x: vec![0.0; nx],
            z: vec![0.0; ni],
            events: 0,
            terminated: false,
            calls: 0,
        };
        let mut driven = me.driven(inst);
        let r = driven
            .finish_event("the initial event iteration")
            .and_then(|stop| {
                if stop.is_some() {
                    return Ok(true);
                }
                // the states, whether or not the event iteration changed them
                driven.fmu.calls += 1;
                let s = driven.fmu.inst.get_continuous_states(&mut driven.x);
                driver::ok(|| "GetContinuousStates".into(), status::<T>(s)).map(|()| false)
            });
        let r = r.map_err(|e| format!("{e}\n{}", driven.fmu.inst.log_tail()));
        me.absorb(driven);
        me.terminated = r?;
        me.events = 0;
        Ok(me)
    }

    /// `steps` steps from an initialized instance: the bits of the states every 10 steps
    /// and of `all_values` every 100; then the number of events, whether the FMU ended the
    /// simulation, and the final time. A run to compare across threads.
    pub fn fingerprint<T: ModelExchangeInstance>(
        inst: &mut T,
        h: f64,
        steps: u64,
        all_values: impl Fn(&mut T) -> Vec<f64>,
    ) -> Result<Vec<u64>, String> {
        let mut me = MeIntegrator::start(inst, h)?;
        let mut out = vec![];
        for n in 0..steps {
            me.step(inst)
                .map_err(|m| format!("step {n} (t = {}): {m}", me.time()))?;
            if n % 10 == 9 {
                out.extend(me.x.iter().map(|x| x.to_bits()));
            }
            if n % 100 == 99 {
                out.extend(all_values(inst).iter().map(|x| x.to_bits()));
            }
        }
        out.extend([me.events, me.terminated as u64, me.time().to_bits()]);
        Ok(out)
    }

    /// The time of step `n`.
    pub fn time(&self) -> f64 {
        self.t0 + self.n as f64 * self.h
    }

    /// The driver at this integrator's accepted point.
    fn driven<'a, T: ModelExchangeInstance>(&self, inst: &'a mut T) -> Integration<Counted<'a, T>> {
        let counted = Counted {
            inst,
            calls: 0,
            events: 0,
        };
        let mut driven = Integration::new(counted, (self.x.len(), self.z.len()), OPTIONS);
        driven.at = Where::Free;
        driven.t = self.time();
        driven.x.copy_from_slice(&self.x);
        driven.z.copy_from_slice(&self.z);
        driven
    }

    /// The driver's point, calls and events, taken back.
    fn absorb<T: ModelExchangeInstance>(&mut self, driven: Integration<Counted<'_, T>>) {
        self.calls += driven.fmu.calls;
        self.events += driven.fmu.events;
        self.x = driven.x;
        self.z = driven.z;
    }

    /// One step of the grid (nothing once the FMU said terminateSimulation).
    pub fn step(&mut self, inst: &mut impl ModelExchangeInstance) -> Result<(), String> {
        if self.terminated {
            return Ok(());
        }
        let t1 = self.t0 + (self.n + 1) as f64 * self.h;
        let mut driven = self.driven(inst);
        let r = driven.integrate_to(t1);
        let r = r.map_err(|e| format!("{e}\n{}", driven.fmu.inst.log_tail()));
        self.absorb(driven);
        self.n += 1;
        self.terminated = r?.is_some();
        Ok(())
    }
}
