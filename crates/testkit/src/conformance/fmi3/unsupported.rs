//! The functions of features this FMU does not offer (clocks, configuration mode,
//! Scheduled Execution, per-element dependencies) and of the variable types it has none of:
//! refused with a message, never a crash.

use super::started;
use crate::fmi3::Fmi3Harness;
use crate::harness::MessageLog;
use mechfmu::fmi3::ffi::*;
use mechfmu::fmi3::functions as f3;
use mechfmu::model::Mechanism;

/// Calls `$f` on the instance with no value reference (fmi3OK) and with one (fmi3Error and a
/// message), a getter or setter of a type this FMU has no variables of, `$values` the
/// buffer of one value.
macro_rules! typed {
    ($fmu:ident, $f:ident, $values:expr $(, $sizes:expr)?) => {{
        let (c, name, vr, mut values) = ($fmu.instance(), stringify!($f), [0u32], $values);
        let (vr, values) = (vr.as_ptr(), values.as_mut_ptr() as _);
        // SAFETY: a live instance, arrays of the lengths given.
        let (empty, one) = unsafe {
            (
                f3::$f::<M>(c, vr, 0, $($sizes.as_mut_ptr(),)? values, 0),
                f3::$f::<M>(c, vr, 1, $($sizes.as_mut_ptr(),)? values, 1),
            )
        };
        let what = "with 0 and 1 value references";
        assert_eq!((empty, one), (fmi3OK, fmi3Error), "{}: {name} {what}", M::NAME);
        let message = format!("{name}: value reference 0 is not a variable of type");
        assert!($fmu.logged(&message), "{}: {message}: {:?}", M::NAME, $fmu.messages());
    }};
}

/// Clocks, configuration mode, model partitions, per-element dependencies and Scheduled
/// Execution are refused with fmi3Error (NULL for the instantiation) and a message naming
/// the function; getters and setters of the types other than Float64 succeed with no value
/// reference and refuse one. The instance goes on.
pub fn unsupported_functions_are_refused<M: Mechanism>() {
    let e = M::EXPERIMENT;
    let mut fmu = started::<M>();
    features_not_offered_are_refused(&fmu);
    types_without_variables_are_refused(&fmu);
    assert_eq!(
        fmu.do_step(e.start, e.step).status,
        fmi3OK,
        "{}: after refused calls: {:?}",
        M::NAME,
        fmu.messages()
    );
    scheduled_execution_is_refused::<M>();
}

/// The functions of clocks, configuration mode, model partitions and per-element
/// dependencies return fmi3Error with a message naming the function.
fn features_not_offered_are_refused<M: Mechanism>(fmu: &Fmi3Harness<M>) {
    let (name, e) = (M::NAME, M::EXPERIMENT);
    let c = fmu.instance();
    let (vr, mut clock, mut n, mut x, mut k, mut q) =
        ([0u32], [false], 0usize, [0.0], [0u64], [0u32]);
    let (mut i, mut j, mut r, mut kind) = ([0usize], [0usize], [0u32], [0u32]);
    // SAFETY: a live instance, valid out-pointers and arrays of the lengths given.
    let calls = unsafe {
        [
            (
                "fmi3GetClock",
                f3::fmi3GetClock::<M>(c, vr.as_ptr(), 1, clock.as_mut_ptr()),
            ),
            (
                "fmi3SetClock",
                f3::fmi3SetClock::<M>(c, vr.as_ptr(), 1, clock.as_ptr()),
            ),
            (
                "fmi3GetIntervalDecimal",
                f3::fmi3GetIntervalDecimal::<M>(c, vr.as_ptr(), 1, x.as_mut_ptr(), q.as_mut_ptr()),
            ),
            (
                "fmi3GetIntervalFraction",
                f3::fmi3GetIntervalFraction::<M>(
                    c,
                    vr.as_ptr(),
                    1,
                    k.as_mut_ptr(),
                    k.as_mut_ptr(),
                    q.as_mut_ptr(),
                ),
            ),
            (
                "fmi3GetShiftDecimal",
                f3::fmi3GetShiftDecimal::<M>(c, vr.as_ptr(), 1, x.as_mut_ptr()),
            ),
            (
                "fmi3GetShiftFraction",
                f3::fmi3GetShiftFraction::<M>(c, vr.as_ptr(), 1, k.as_mut_ptr(), k.as_mut_ptr()),
            ),
            (
                "fmi3SetIntervalDecimal",
                f3::fmi3SetIntervalDecimal::<M>(c, vr.as_ptr(), 1, x.as_ptr()),
            ),
            (
                "fmi3SetIntervalFraction",
                f3::fmi3SetIntervalFraction::<M>(c, vr.as_ptr(), 1, k.as_ptr(), k.as_ptr()),
            ),
            (
                "fmi3SetShiftDecimal",
                f3::fmi3SetShiftDecimal::<M>(c, vr.as_ptr(), 1, x.as_ptr()),
            ),
            (
                "fmi3SetShiftFraction",
                f3::fmi3SetShiftFraction::<M>(c, vr.as_ptr(), 1, k.as_ptr(), k.as_ptr()),
            ),
            (
                "fmi3EnterConfigurationMode",
                f3::fmi3EnterConfigurationMode::<M>(c),
            ),
            (
                "fmi3ExitConfigurationMode",
                f3::fmi3ExitConfigurationMode::<M>(c),
            ),
            (
                "fmi3ActivateModelPartition",
                f3::fmi3ActivateModelPartition::<M>(c, 0, e.start),
            ),
            (
                "fmi3GetNumberOfVariableDependencies",
                f3::fmi3GetNumberOfVariableDependencies::<M>(c, 0, &mut n),
            ),
            (
                "fmi3GetVariableDependencies",
                f3::fmi3GetVariableDependencies::<M>(
                    c,
                    0,
                    i.as_mut_ptr(),
                    r.as_mut_ptr(),
                    j.as_mut_ptr(),
                    kind.as_mut_ptr(),
                    1,
                ),
            ),
        ]
    };
    for (function, status) in calls {
        assert_eq!(
            status, fmi3Error,
            "{name}: {function} is not offered, yet returned {status}"
        );
        assert!(
            fmu.messages()
                .iter()
                .any(|(s, _, m)| *s == fmi3Error && m.starts_with(&format!("{function}: "))),
            "{name}: {function} refused without a message: {:?}",
            fmu.messages()
        );
    }
}

/// Every getter and setter of a type other than Float64 (this FMU has no variables of
/// them) succeeds with no value reference and refuses one with a message.
fn types_without_variables_are_refused<M: Mechanism>(fmu: &Fmi3Harness<M>) {
    typed!(fmu, fmi3GetFloat32, [0f32]);
    typed!(fmu, fmi3GetInt8, [0i8]);
    typed!(fmu, fmi3GetUInt8, [0u8]);
    typed!(fmu, fmi3GetInt16, [0i16]);
    typed!(fmu, fmi3GetUInt16, [0u16]);
    typed!(fmu, fmi3GetInt32, [0i32]);
    typed!(fmu, fmi3GetUInt32, [0u32]);
    typed!(fmu, fmi3GetInt64, [0i64]);
    typed!(fmu, fmi3GetUInt64, [0u64]);
    typed!(fmu, fmi3GetBoolean, [false]);
    typed!(fmu, fmi3GetString, [std::ptr::null::<std::ffi::c_char>()]);
    typed!(fmu, fmi3GetBinary, [std::ptr::null::<u8>()], [0usize]);
    typed!(fmu, fmi3SetFloat32, [0f32]);
    typed!(fmu, fmi3SetInt8, [0i8]);
    typed!(fmu, fmi3SetUInt8, [0u8]);
    typed!(fmu, fmi3SetInt16, [0i16]);
    typed!(fmu, fmi3SetUInt16, [0u16]);
    typed!(fmu, fmi3SetInt32, [0i32]);
    typed!(fmu, fmi3SetUInt32, [0u32]);
    typed!(fmu, fmi3SetInt64, [0i64]);
    typed!(fmu, fmi3SetUInt64, [0u64]);
    typed!(fmu, fmi3SetBoolean, [false]);
    typed!(fmu, fmi3SetString, [c"text".as_ptr()]);
    typed!(
        fmu,
        fmi3SetBinary,
        [c"bytes".as_ptr() as *const u8],
        [5usize]
    );
}

/// fmi3InstantiateScheduledExecution gives no instance, and says why.
fn scheduled_execution_is_refused<M: Mechanism>() {
    let name = M::NAME;
    let log = MessageLog::new();
    let token =
        std::ffi::CString::new(mechfmu::contract::instantiation_token::<M>()).unwrap_or_default();
    // SAFETY: valid strings, a logger environment that outlives the call.
    let instance = unsafe {
        f3::fmi3InstantiateScheduledExecution::<M>(
            c"scheduled".as_ptr(),
            token.as_ptr(),
            std::ptr::null(),
            false,
            true,
            log.environment(),
            Some(crate::fmi3::record),
            None,
            None,
            None,
        )
    };
    assert!(
        instance.is_null(),
        "{name}: fmi3InstantiateScheduledExecution gave an instance"
    );
    let said = log
        .messages()
        .iter()
        .any(|(_, _, m)| m.starts_with("fmi3InstantiateScheduledExecution: "));
    assert!(
        said,
        "{name}: fmi3InstantiateScheduledExecution without a message: {:?}",
        log.messages()
    );
}
