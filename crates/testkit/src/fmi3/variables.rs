//! FMI 3.0's variables on an [`Fmi3Harness`]: by value reference (arrays whole, `time`)
//! and by name (scalars, array elements).

use super::{ok, Fmi3Harness};
use crate::harness::Harness;
use mechfmu::fmi3::ffi::*;
use mechfmu::fmi3::functions;
use mechfmu::model::{Mechanism, Shapes};

impl<M: Mechanism> Fmi3Harness<M> {
    /// The value reference of `time`.
    pub fn time_vr(&self) -> fmi3ValueReference {
        Shapes::TIME_REFERENCE as fmi3ValueReference
    }

    /// The FMI 3.0 value reference of a variable (scalar or array) or of `time`, by name
    /// (panics on a name that is neither: a test bug).
    pub fn vr(&self, name: &str) -> fmi3ValueReference {
        if name == "time" {
            return self.time_vr();
        }
        (self.shapes.variables.iter().find(|s| s.name == name))
            .unwrap_or_else(|| panic!("{} has no FMI 3.0 variable `{name}`", M::NAME))
            .reference as fmi3ValueReference
    }

    /// The number of values the variables `vrs` have (an unknown one counts 1).
    pub fn len_of(&self, vrs: &[fmi3ValueReference]) -> usize {
        vrs.iter()
            .map(|&vr| self.shapes.get(vr as usize).map_or(1, |s| s.elements.len()))
            .sum()
    }

    /// `(value reference, position)` of a scalar, `time`, an array element written
    /// `A[i,j]` or an array element by its scalar's name (its first place).
    fn locate(&self, name: &str) -> (fmi3ValueReference, usize) {
        if let Some(s) = self.shapes.variables.iter().find(|s| s.name == name) {
            assert!(!s.is_array(), "{name} is an array: use get_array");
            return (s.reference as fmi3ValueReference, 0);
        }
        if name == "time" {
            return (self.time_vr(), 0);
        }
        if let Some((array, _)) = name.split_once('[') {
            let s = (self.shapes.variables.iter().find(|s| s.name == array))
                .unwrap_or_else(|| panic!("{} has no array `{array}`", M::NAME));
            let k = (0..s.elements.len())
                .find(|&k| s.element_name(k) == name)
                .unwrap_or_else(|| panic!("{} has no element {name}", M::NAME));
            return (s.reference as fmi3ValueReference, k);
        }
        let scalar = Harness::<M>::vr(name) as usize;
        let owner = self
            .shapes
            .owner(scalar)
            .expect("every scalar has an owner");
        let k = owner
            .elements
            .iter()
            .position(|&e| e == scalar)
            .unwrap_or(0);
        (owner.reference as fmi3ValueReference, k)
    }

    /// `fmi3GetFloat64` with `nValues = values.len()`.
    pub fn get_float64(&mut self, vrs: &[fmi3ValueReference], values: &mut [f64]) -> fmi3Status {
        // SAFETY: live instance, arrays of the given lengths.
        unsafe {
            functions::fmi3GetFloat64::<M>(
                self.instance,
                vrs.as_ptr(),
                vrs.len(),
                values.as_mut_ptr(),
                values.len(),
            )
        }
    }

    /// `fmi3SetFloat64` with `nValues = values.len()`.
    pub fn set_float64(&mut self, vrs: &[fmi3ValueReference], values: &[f64]) -> fmi3Status {
        // SAFETY: live instance, arrays of the given lengths.
        unsafe {
            functions::fmi3SetFloat64::<M>(
                self.instance,
                vrs.as_ptr(),
                vrs.len(),
                values.as_ptr(),
                values.len(),
            )
        }
    }

    /// The values of the variables `vrs`, arrays element by element in row-major order.
    pub fn get_values(&mut self, vrs: &[fmi3ValueReference]) -> Result<Vec<f64>, fmi3Status> {
        let mut values = vec![f64::NAN; self.len_of(vrs)];
        let status = self.get_float64(vrs, &mut values);
        ok(status, values)
    }

    /// An array variable's elements by its name (panics if the call fails).
    pub fn get_array(&mut self, name: &str) -> Vec<f64> {
        let vr = self.vr(name);
        self.get_values(&[vr])
            .unwrap_or_else(|s| panic!("{}: getting {name}: {s}: {:?}", M::NAME, self.messages()))
    }

    /// One scalar or array element by name (see the module's documentation; NaN if the
    /// call fails).
    pub fn get(&mut self, name: &str) -> f64 {
        let (vr, k) = self.locate(name);
        self.get_values(&[vr]).map_or(f64::NAN, |v| v[k])
    }

    /// Sets one scalar by name; an array element by setting its array, with every place
    /// of the element's scalar set to `value`.
    pub fn set(&mut self, name: &str, value: f64) -> fmi3Status {
        let (vr, k) = self.locate(name);
        let Some(shaped) = self
            .shapes
            .get(vr as usize)
            .filter(|s| s.is_array())
            .cloned()
        else {
            return self.set_float64(&[vr], &[value]);
        };
        let mut values = match self.get_values(&[vr]) {
            Ok(values) => values,
            Err(status) => return status,
        };
        for (x, &e) in values.iter_mut().zip(&shaped.elements) {
            if e == shaped.elements[k] {
                *x = value;
            }
        }
        self.set_float64(&[vr], &values)
    }

    /// Every scalar's value by FMI 2.0 value reference, read through FMI 3.0's variables
    /// in one call.
    pub fn all_values(&mut self) -> Vec<f64> {
        let vrs: Vec<u32> = self
            .shapes
            .variables
            .iter()
            .map(|s| s.reference as u32)
            .collect();
        let mut scalars = vec![f64::NAN; M::VARIABLES.len()];
        if let Ok(values) = self.get_values(&vrs) {
            let elements = self.shapes.variables.iter().flat_map(|s| &s.elements);
            for (&e, x) in elements.zip(values) {
                scalars[e] = x;
            }
        }
        scalars
    }
}

#[cfg(test)]
mod tests {
    use crate::fmi3::Fmi3Harness;
    use mechfmu::model::{Array, Experiment, Mechanism, Scalar, Variable};

    mechfmu::mechanism! {
        /// Two coupled decays, y' = -A y with a symmetric A.
        pub struct Coupled / CoupledValues {
            /// Diagonal rate
            a11: Variable::parameter("1/s", 1.0),
            /// Coupling rate
            a12: Variable::parameter("1/s", 0.0),
            /// Diagonal rate
            a22: Variable::parameter("1/s", 2.0),
            /// First amount
            y1: Variable::state("1", 1.0, "y1_dot"),
            /// Second amount
            y2: Variable::state("1", 1.0, "y2_dot"),
            /// Rate of change of the first amount
            y1_dot: Variable::output("1/s"),
            /// Rate of change of the second amount
            y2_dot: Variable::output("1/s"),
        }
    }

    impl Mechanism for Coupled {
        const EXPERIMENT: Experiment = crate::harness::ONE_SECOND;
        const ARRAYS: &'static [Array] = &[
            Array::new("A", "Rates", &[2, 2], &["a11", "a12", "a12", "a22"]),
            Array::new("y", "Amounts", &[2], &["y1", "y2"]),
            Array::new("y_dot", "Rates of change", &[2], &["y1_dot", "y2_dot"]),
        ];
        fn evaluate<S: Scalar>(v: &mut CoupledValues<S>) {
            v.y1_dot = -(v.a11 * v.y1 + v.a12 * v.y2);
            v.y2_dot = -(v.a12 * v.y1 + v.a22 * v.y2);
        }
    }

    /// An element by its place or by its scalar's name sets every place of that scalar, and
    /// reads back from either.
    #[test]
    fn elements_are_reached_by_place_and_by_scalar_name() {
        let mut fmu = Fmi3Harness::<Coupled>::new();
        fmu.initialize(None, 0.0, &[("A[2,1]", 0.5), ("y2", 3.0), ("a22", 4.0)])
            .unwrap();
        assert_eq!(fmu.get_array("A"), [1.0, 0.5, 0.5, 4.0]);
        assert_eq!((fmu.get("a12"), fmu.get("A[1,2]")), (0.5, 0.5));
        assert_eq!(fmu.get_array("y"), [1.0, 3.0]);
        assert_eq!(fmu.get("y_dot[2]"), -(0.5 + 4.0 * 3.0));
        assert_eq!((fmu.vr("A"), fmu.vr("y"), fmu.vr("time")), (1, 2, 0));
        assert_eq!(fmu.len_of(&[1, 2, 0]), 4 + 2 + 1);
        fmu.step_to(0.3, 0.1).unwrap();
        assert_eq!(fmu.get("time"), fmu.time());
        let values = fmu.all_values();
        assert_eq!(values[1], 0.5);
        assert_eq!(values[3..5], fmu.get_array("y")[..]);
    }
}
