//! FMU states and derivatives through FMI 3.0, on an [`Fmi3Harness`].

use super::{ok, Fmi3Harness};
use mechfmu::fmi3::ffi::*;
use mechfmu::fmi3::functions;
use mechfmu::model::Mechanism;

/// `fmi3GetDirectionalDerivative` and `fmi3GetAdjointDerivative`.
type DerivativeCall = unsafe extern "C" fn(
    fmi3Instance,
    *const fmi3ValueReference,
    usize,
    *const fmi3ValueReference,
    usize,
    *const fmi3Float64,
    usize,
    *mut fmi3Float64,
    usize,
) -> fmi3Status;

// These take FMU-state handles as the C API does, unchecked, because tests must be able to
// pass stale or foreign ones (an FMI 2.0 state among them): the FMU validates every handle.
#[allow(clippy::not_unsafe_ptr_arg_deref)]
impl<M: Mechanism> Fmi3Harness<M> {
    /// `fmi3GetFMUState` into a fresh handle.
    pub fn get_fmu_state(&mut self) -> Result<fmi3FMUState, fmi3Status> {
        let mut state: fmi3FMUState = std::ptr::null_mut();
        // SAFETY: live instance; `state` is a valid out-pointer.
        let status = unsafe { functions::fmi3GetFMUState::<M>(self.instance, &mut state) };
        ok(status, state)
    }

    pub fn set_fmu_state(&mut self, state: fmi3FMUState) -> fmi3Status {
        // SAFETY: live instance; the FMU checks the handle.
        unsafe { functions::fmi3SetFMUState::<M>(self.instance, state) }
    }

    pub fn free_fmu_state(&mut self, mut state: fmi3FMUState) -> fmi3Status {
        // SAFETY: live instance; the FMU checks the handle.
        unsafe { functions::fmi3FreeFMUState::<M>(self.instance, &mut state) }
    }

    /// Serialized bytes of a state handle.
    pub fn serialize(&mut self, state: fmi3FMUState) -> Result<Vec<u8>, fmi3Status> {
        let mut size = 0usize;
        // SAFETY: live instance, a valid out-pointer.
        let status =
            unsafe { functions::fmi3SerializedFMUStateSize::<M>(self.instance, state, &mut size) };
        ok(status, ())?;
        let mut bytes = vec![0u8; size];
        // SAFETY: live instance, a buffer of `size` bytes.
        let status = unsafe {
            functions::fmi3SerializeFMUState::<M>(self.instance, state, bytes.as_mut_ptr(), size)
        };
        ok(status, bytes)
    }

    /// A new state handle from serialized bytes.
    pub fn deserialize(&mut self, bytes: &[u8]) -> Result<fmi3FMUState, fmi3Status> {
        let mut state: fmi3FMUState = std::ptr::null_mut();
        // SAFETY: live instance; `bytes` is a valid buffer, `state` a valid out-pointer.
        let status = unsafe {
            functions::fmi3DeserializeFMUState::<M>(
                self.instance,
                bytes.as_ptr(),
                bytes.len(),
                &mut state,
            )
        };
        ok(status, state)
    }

    /// `fmi3GetDirectionalDerivative` with `nSeed = seed.len()`, `nSensitivity =
    /// sensitivity.len()`.
    pub fn directional_derivative(
        &mut self,
        unknowns: &[fmi3ValueReference],
        knowns: &[fmi3ValueReference],
        seed: &[f64],
        sensitivity: &mut [f64],
    ) -> fmi3Status {
        let call = functions::fmi3GetDirectionalDerivative::<M>;
        self.derivative(call, (unknowns, knowns), seed, sensitivity)
    }

    /// `fmi3GetAdjointDerivative`, as [`directional_derivative`](Self::directional_derivative).
    pub fn adjoint_derivative(
        &mut self,
        unknowns: &[fmi3ValueReference],
        knowns: &[fmi3ValueReference],
        seed: &[f64],
        sensitivity: &mut [f64],
    ) -> fmi3Status {
        let call = functions::fmi3GetAdjointDerivative::<M>;
        self.derivative(call, (unknowns, knowns), seed, sensitivity)
    }

    /// One of the two derivative calls, which share their C signature.
    fn derivative(
        &mut self,
        call: DerivativeCall,
        (unknowns, knowns): (&[fmi3ValueReference], &[fmi3ValueReference]),
        seed: &[f64],
        sensitivity: &mut [f64],
    ) -> fmi3Status {
        // SAFETY: live instance, arrays of the given lengths.
        unsafe {
            call(
                self.instance,
                unknowns.as_ptr(),
                unknowns.len(),
                knowns.as_ptr(),
                knowns.len(),
                seed.as_ptr(),
                seed.len(),
                sensitivity.as_mut_ptr(),
                sensitivity.len(),
            )
        }
    }

    /// `fmi3GetOutputDerivatives` (one order per variable) with `nValues = values.len()`.
    pub fn output_derivatives(
        &mut self,
        vrs: &[fmi3ValueReference],
        orders: &[i32],
        values: &mut [f64],
    ) -> fmi3Status {
        assert_eq!(vrs.len(), orders.len());
        // SAFETY: live instance, arrays of the given lengths.
        unsafe {
            functions::fmi3GetOutputDerivatives::<M>(
                self.instance,
                vrs.as_ptr(),
                vrs.len(),
                orders.as_ptr(),
                values.as_mut_ptr(),
                values.len(),
            )
        }
    }
}
