//! An importer's fixed-step Model Exchange integrator, over an instance of either
//! standard ([`ModelExchangeInstance`]).

use crate::ffi::*;
use crate::importer::ModelExchangeInstance;

/// An importer's Model Exchange integrator, of either standard: fixed-step classical
/// Runge-Kutta (RK4) through SetTime, SetContinuousStates and GetDerivatives
/// (fmi3GetContinuousStateDerivatives), the time of step n computed as t0 + n·h; after each
/// step CompletedIntegratorStep and GetEventIndicators, and an event (EnterEventMode, the
/// event iteration of fmi2NewDiscreteStates or fmi3UpdateDiscreteStates,
/// EnterContinuousTimeMode) where an indicator changes sign or the FMU asks for one (no
/// event location: the event is taken at the end of the step).
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
    k: [Vec<f64>; 4],
    tmp: Vec<f64>,
}

fn ok(what: &str, s: Status, inst: &impl ModelExchangeInstance) -> Result<(), String> {
    if matches!(s, OK | WARNING) {
        Ok(())
    } else {
        Err(format!(
            "{what} returned {}\n{}",
            status_name(s),
            inst.log_tail()
        ))
    }
}

impl MeIntegrator {
    /// Takes over an initialized Model Exchange instance (in event mode): the event
    /// iteration at the start, continuous-time mode, the states and indicators.
    pub fn start(inst: &mut impl ModelExchangeInstance, h: f64) -> Result<MeIntegrator, String> {
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
            k: std::array::from_fn(|_| vec![0.0; nx]),
            tmp: vec![0.0; nx],
        };
        me.event(inst)?;
        me.events = 0;
        Ok(me)
    }

    /// The time of step `n`.
    pub fn time(&self) -> f64 {
        self.t0 + self.n as f64 * self.h
    }

    /// From event mode: the event iteration, then continuous-time mode; reads the states
    /// (the FMU may have changed them) and the indicators.
    fn event(&mut self, inst: &mut impl ModelExchangeInstance) -> Result<(), String> {
        let mut iterations = 0;
        loop {
            let (s, needed, terminate) = inst.update_discrete_states();
            self.calls += 1;
            ok("the event iteration", s, inst)?;
            iterations += 1;
            if terminate {
                self.terminated = true;
                return Ok(());
            }
            if !needed {
                break;
            }
            if iterations == 100 {
                return Err("the event iteration did not end in 100 iterations".into());
            }
        }
        ok(
            "EnterContinuousTimeMode",
            inst.enter_continuous_time_mode(),
            inst,
        )?;
        let s = inst.get_continuous_states(&mut self.x);
        ok("GetContinuousStates", s, inst)?;
        let s = inst.get_event_indicators(&mut self.z);
        ok("GetEventIndicators", s, inst)?;
        self.calls += 3;
        self.events += 1;
        Ok(())
    }

    /// `dx` = f(t, x).
    fn f(
        inst: &mut impl ModelExchangeInstance,
        t: f64,
        x: &[f64],
        dx: &mut [f64],
    ) -> Result<(), String> {
        ok("SetTime", inst.set_time(t), inst)?;
        ok("SetContinuousStates", inst.set_continuous_states(x), inst)?;
        let s = inst.get_derivatives(dx);
        ok("GetDerivatives", s, inst)
    }

    /// One RK4 step (nothing once the FMU said terminateSimulation).
    pub fn step(&mut self, inst: &mut impl ModelExchangeInstance) -> Result<(), String> {
        if self.terminated {
            return Ok(());
        }
        let (t, h) = (self.time(), self.h);
        let t1 = self.t0 + (self.n + 1) as f64 * h;
        let tm = t + 0.5 * h;
        let [k1, k2, k3, k4] = &mut self.k;
        let tmp = &mut self.tmp;
        Self::f(inst, t, &self.x, k1)?;
        for ((y, x), k) in tmp.iter_mut().zip(&self.x).zip(k1.iter()) {
            *y = x + 0.5 * h * k;
        }
        Self::f(inst, tm, tmp, k2)?;
        for ((y, x), k) in tmp.iter_mut().zip(&self.x).zip(k2.iter()) {
            *y = x + 0.5 * h * k;
        }
        Self::f(inst, tm, tmp, k3)?;
        for ((y, x), k) in tmp.iter_mut().zip(&self.x).zip(k3.iter()) {
            *y = x + h * k;
        }
        Self::f(inst, t1, tmp, k4)?;
        for (i, x) in self.x.iter_mut().enumerate() {
            *x += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
        ok("SetTime", inst.set_time(t1), inst)?;
        ok(
            "SetContinuousStates",
            inst.set_continuous_states(&self.x),
            inst,
        )?;
        self.calls += 14;
        self.n += 1;
        let (s, enter, terminate) = inst.completed_integrator_step(true);
        ok("CompletedIntegratorStep", s, inst)?;
        let mut z = vec![0.0; self.z.len()];
        let s = inst.get_event_indicators(&mut z);
        ok("GetEventIndicators", s, inst)?;
        self.calls += 2;
        if terminate {
            self.terminated = true;
            return Ok(());
        }
        let crossed = self.z.iter().zip(&z).any(|(a, b)| (*a > 0.0) != (*b > 0.0));
        self.z = z;
        if enter || crossed {
            ok("EnterEventMode", inst.enter_event_mode(), inst)?;
            self.calls += 1;
            self.event(inst)?;
        }
        Ok(())
    }
}
