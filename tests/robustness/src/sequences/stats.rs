//! Counts over a run of sequences.

/// Counts over a run.
#[derive(Clone, Debug, Default)]
pub struct Stats {
    pub sequences: u64,
    pub calls: u64,
    pub statuses: [u64; 6],
    pub steps_ok: u64,
    pub steps_discarded: u64,
    pub illegal_calls: u64,
    pub states_restored: u64,
    pub deserialized: u64,
    pub me_instances: u64,
    pub me_steps: u64,
    pub events: u64,
    /// FMI 3.0: Co-Simulation instances with event mode, steps that returned early.
    pub cs_event_mode_instances: u64,
    pub early_returns: u64,
}

impl Stats {
    pub fn add(&mut self, o: &Stats) {
        self.sequences += o.sequences;
        self.calls += o.calls;
        for i in 0..6 {
            self.statuses[i] += o.statuses[i];
        }
        self.steps_ok += o.steps_ok;
        self.steps_discarded += o.steps_discarded;
        self.illegal_calls += o.illegal_calls;
        self.states_restored += o.states_restored;
        self.deserialized += o.deserialized;
        self.me_instances += o.me_instances;
        self.me_steps += o.me_steps;
        self.events += o.events;
        self.cs_event_mode_instances += o.cs_event_mode_instances;
        self.early_returns += o.early_returns;
    }
}

impl std::fmt::Display for Stats {
    fn fmt(&self, w: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(
            w,
            "{} sequences, {} calls (OK {}, Warning {}, Discard {}, Error {}), {} steps OK, {} discarded, {} illegal calls refused, {} states restored, {} deserialized, {} Model Exchange instances, {} integrator steps, {} event iterations",
            self.sequences,
            self.calls,
            self.statuses[0],
            self.statuses[1],
            self.statuses[2],
            self.statuses[3],
            self.steps_ok,
            self.steps_discarded,
            self.illegal_calls,
            self.states_restored,
            self.deserialized,
            self.me_instances,
            self.me_steps,
            self.events
        )?;
        // Only FMI 3.0 has these.
        if self.cs_event_mode_instances + self.early_returns > 0 {
            write!(
                w,
                ", {} Co-Simulation instances with event mode, {} early returns",
                self.cs_event_mode_instances, self.early_returns
            )?;
        }
        Ok(())
    }
}
