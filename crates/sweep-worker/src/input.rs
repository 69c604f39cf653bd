//! A case's input table, interpolated as `FastInput` in `python/mechfmu_sweep/runner.py`
//! does it (itself fmpy's `Input` for continuous Real inputs): the same index searches, the
//! same `isclose` tests and the same floating-point operations in the same order, so the
//! same values to the bit.

use crate::pymath::{bisect_left, bisect_right, isclose};

/// One case's table (time, then one column per input), kept between cases so loading the
/// next one reuses its memory.
pub struct InputTable {
    times: Vec<f64>,
    /// Column-major: input `j`'s values at `j * rows..(j + 1) * rows`.
    columns: Vec<f64>,
    n_inputs: usize,
    /// The times where the table steps (a time repeated), sorted, then `+inf`.
    events: Vec<f64>,
    /// The values of the last [`InputTable::values_at`], one per input.
    values: Vec<f64>,
}

impl InputTable {
    pub fn new(n_inputs: usize) -> InputTable {
        InputTable {
            times: Vec::new(),
            columns: Vec::new(),
            n_inputs,
            events: Vec::new(),
            values: vec![0.0; n_inputs],
        }
    }

    /// Loads a table of `n_rows` rows given row-major, `row_major(k)` being value `k` of
    /// `time, input 0, input 1, ...` repeated per row.
    pub fn load(&mut self, n_rows: usize, row_major: impl Fn(usize) -> f64) {
        let width = 1 + self.n_inputs;
        self.times.clear();
        self.times.extend((0..n_rows).map(|r| row_major(r * width)));
        self.columns.clear();
        for j in 0..self.n_inputs {
            self.columns
                .extend((0..n_rows).map(|r| row_major(r * width + 1 + j)));
        }
        self.find_events();
    }

    /// `sorted({t[i] for i in range(n - 1) if t[i + 1] - t[i] == 0} | {inf})`: a stable
    /// sort, then the first of equal values kept, as the set keeps the first it was given
    /// (`0.0` and `-0.0` are one member).
    fn find_events(&mut self) {
        self.events.clear();
        let t = &self.times;
        self.events.extend(
            t.windows(2)
                .filter(|pair| pair[1] - pair[0] == 0.0)
                .map(|pair| pair[0]),
        );
        self.events.push(f64::INFINITY);
        // No NaN gets here (NaN - x is never 0), so the order is total.
        self.events
            .sort_by(|a, b| a.partial_cmp(b).unwrap_or(std::cmp::Ordering::Equal));
        self.events.dedup_by(|later, first| later == first);
    }

    /// `FastInput.values_at(time, after_event)`.
    pub fn values_at(&mut self, time: f64, after_event: bool) -> &[f64] {
        let t = &self.times;
        let n = t.len();
        if n == 0 {
            return &self.values; // no table: a caller never asks (a case without input)
        }
        if n < 2 {
            return self.row(0);
        }
        let mut i0 = bisect_left(t, time);
        if i0 == 0 {
            return self.row(0);
        }
        if i0 == n {
            return self.row(n - 1);
        }
        if isclose(time, t[i0]) && i0 < n - 1 && isclose(t[i0], t[i0 + 1]) {
            if after_event {
                while i0 < n - 1 && isclose(t[i0], t[i0 + 1]) {
                    i0 += 1;
                }
            }
            return self.row(i0);
        }
        i0 -= 1;
        let (t0, t1) = (t[i0], t[i0 + 1]);
        let w0 = (t1 - time) / (t1 - t0);
        let w1 = 1.0 - w0;
        for (j, value) in self.values.iter_mut().enumerate() {
            let column = &self.columns[j * n..(j + 1) * n];
            *value = w0 * column[i0] + w1 * column[i0 + 1];
        }
        &self.values
    }

    /// The inputs' values at row `i`.
    fn row(&mut self, i: usize) -> &[f64] {
        let n = self.times.len();
        for (j, value) in self.values.iter_mut().enumerate() {
            *value = self.columns[j * n + i];
        }
        &self.values
    }

    /// `FastInput.nextEvent(time)`: the first step time after `time` and not close to it.
    pub fn next_event(&self, time: f64) -> f64 {
        let events = &self.events;
        let mut i = bisect_right(events, time);
        // Python would raise IndexError past the end, which only `time = inf` reaches;
        // the worker's times are finite, and +inf is the answer there anyway.
        while i < events.len() && isclose(events[i], time) {
            i += 1;
        }
        events.get(i).copied().unwrap_or(f64::INFINITY)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Times 0, 1, 1, 2, 3 (a step at 1) and two inputs.
    fn stepped_table() -> InputTable {
        let rows: [[f64; 3]; 5] = [
            [0.0, 0.0, 1.0],
            [1.0, 10.0, 0.1],
            [1.0, 20.0, 0.3],
            [2.0, 30.0, 0.7],
            [3.0, -7.0, 0.9],
        ];
        let mut table = InputTable::new(2);
        table.load(rows.len(), |k| rows[k / 3][k % 3]);
        table
    }

    #[test]
    fn values_are_fastinputs_to_the_bit() {
        // FastInput.values_at(time, after_event) on the same table, Python 3.11.
        let expected: [(f64, bool, [u64; 2]); 11] = [
            (0.5, false, [0x4014000000000000, 0x3fe199999999999a]),
            (1.0, false, [0x4024000000000000, 0x3fb999999999999a]),
            (1.0, true, [0x4034000000000000, 0x3fd3333333333333]),
            (1.5, false, [0x4039000000000000, 0x3fe0000000000000]),
            (-1.0, true, [0x0000000000000000, 0x3ff0000000000000]),
            (9.0, false, [0xc01c000000000000, 0x3feccccccccccccd]),
            (2.0, false, [0x403e000000000000, 0x3fe6666666666666]),
            (2.7, true, [0x401066666666665f, 0x3feae147ae147ae2]),
            (1.0000000001, true, [0x4034000000044b83, 0x3fd33333333e31f3]),
            (0.3, false, [0x4008000000000001, 0x3fe75c28f5c28f5c]),
            (2.2, false, [0x4036999999999997, 0x3fe7ae147ae147ae]),
        ];
        let mut table = stepped_table();
        for (time, after_event, bits) in expected {
            let values = table.values_at(time, after_event);
            let got = [values[0].to_bits(), values[1].to_bits()];
            assert_eq!(got, bits, "values_at({time}, {after_event}): {values:?}");
        }
    }

    #[test]
    fn the_next_event_is_the_step_then_infinity() {
        let table = stepped_table();
        assert_eq!(table.events, [1.0, f64::INFINITY]);
        assert_eq!(table.next_event(-3.0), 1.0);
        assert_eq!(table.next_event(0.0), 1.0);
        // Close to the step counts as at it: the next one is after it.
        assert_eq!(table.next_event(0.9999999999), f64::INFINITY);
        assert_eq!(table.next_event(1.0), f64::INFINITY);
        assert_eq!(table.next_event(5.0), f64::INFINITY);
        assert_eq!(table.next_event(f64::INFINITY), f64::INFINITY);
    }

    #[test]
    fn repeated_steps_are_one_event_each() {
        let times = [0.0, 2.0, 2.0, 1.0, 1.0, 2.0, 2.0];
        let mut table = InputTable::new(0);
        table.load(times.len(), |k| times[k]);
        assert_eq!(table.events, [1.0, 2.0, f64::INFINITY]);
    }

    #[test]
    fn a_single_row_is_held() {
        let mut table = InputTable::new(1);
        table.load(1, |k| [4.0, 7.5][k]);
        assert_eq!(table.values_at(-1.0, false), [7.5]);
        assert_eq!(table.values_at(100.0, true), [7.5]);
        assert_eq!(table.next_event(0.0), f64::INFINITY);
    }

    #[test]
    fn a_table_reloads_in_place() {
        let mut table = stepped_table();
        table.load(2, |k| [0.0, 1.0, 2.0, 1.0, 3.0, 5.0][k]);
        assert_eq!(table.times.len(), 2);
        assert_eq!(table.values_at(0.5, false), [2.0, 3.5]);
        assert_eq!(table.events, [f64::INFINITY]);
    }
}
