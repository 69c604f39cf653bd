//! A system's values as one mechanism's: the time, then each component's values (its own
//! time first, then its variables), one after the other. The system's value references number
//! the components' variables in that order, so a component's equations run on its own values
//! where they lie, with nothing copied but what the connections carry.
//!
//! The components are a list in types, `(A, (B, (C, ())))`, which [`system!`](crate::system)
//! writes down; [`Components`] walks it, so each call on "component `k`" becomes a call on a
//! known type once `k` is a constant.

use crate::model::{Fields, Mechanism, Monitor, Scalar, ValueSet};

/// The values of a system of [`Components`] `L`.
#[repr(C)]
pub struct SystemValues<S: Scalar, L: Components> {
    /// Simulation time (s); each component's own time follows it.
    pub time: S,
    pub components: L::Values<S>,
}

/// Two things laid out one after the other: a component's values and the rest's.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct Pair<H, T> {
    pub head: H,
    pub tail: T,
}

impl<S: Scalar, L: Components> Clone for SystemValues<S, L> {
    fn clone(&self) -> Self {
        SystemValues {
            time: self.time,
            components: self.components.clone(),
        }
    }
}

// SAFETY: `SystemValues` is repr(C): the time, then `L::Values<S>`, a repr(C) nest of `Pair`s of
// components' values (each a repr(C) struct of `S` fields, as `Fields` requires of it) ending in
// `()`. Every field is an `S`, `LEN` in all; `model::values` checks at compile time that the
// struct has exactly the size and alignment of `[S; LEN]` (no padding) before reading it so.
unsafe impl<S: Scalar, L: Components> Fields<S> for SystemValues<S, L> {
    const LEN: usize = 1 + L::FIELDS;

    #[inline(always)]
    fn field_of(vr: usize) -> Option<usize> {
        L::field_of(vr, 1)
    }

    #[inline(always)]
    fn reference_at(field: usize) -> Option<usize> {
        L::reference_at(field.checked_sub(1)?, 0)
    }
}

impl<S: Scalar, L: Components> ValueSet<S> for SystemValues<S, L> {
    #[inline]
    fn time(&self) -> S {
        self.time
    }

    /// The system's time and each component's.
    #[inline]
    fn set_time(&mut self, t: S) {
        self.time = t;
        L::set_time(&mut self.components, t);
    }
}

/// A list of mechanisms, `(A, (B, ()))`: the components of a system, in the order declared.
/// Implemented for the lists [`system!`](crate::system) writes; component `k` is the `k`-th.
pub trait Components: Send + Sync + 'static {
    /// The components' values, one after the other.
    type Values<S: Scalar>: Clone + Send + 'static;
    /// The number of fields of those values (each component's variables and its time).
    const FIELDS: usize;
    /// The number of variables.
    const VARIABLES: usize;
    /// Whether any component projects its states.
    const PROJECTED: bool;
    /// Whether any component monitors its validity.
    const MONITORED: bool;

    fn zeros<S: Scalar>() -> Self::Values<S>;
    fn map<A: Scalar, B: Scalar>(values: &Self::Values<A>, f: &impl Fn(A) -> B) -> Self::Values<B>;
    fn set_time<S: Scalar>(values: &mut Self::Values<S>, t: S);
    /// The field of value reference `vr` (numbered from this list's first variable), when
    /// this list's first field is field `first` of the system.
    fn field_of(vr: usize, first: usize) -> Option<usize>;
    /// The value reference field `field` of this list holds, when its first variable is
    /// value reference `first`.
    fn reference_at(field: usize, first: usize) -> Option<usize>;
    /// Component `k`'s [`Mechanism::evaluate`], then its [`Mechanism::outputs`] when
    /// `outputs`.
    fn evaluate<S: Scalar>(values: &mut Self::Values<S>, k: usize, outputs: bool);
    /// Component `k`'s [`Mechanism::outputs`].
    fn outputs<S: Scalar>(values: &mut Self::Values<S>, k: usize);
    /// Component `k`'s [`Mechanism::calculate`].
    fn calculate(values: &mut Self::Values<f64>, k: usize) -> Result<(), String>;
    /// Component `k`'s [`Mechanism::diagnose`].
    fn diagnose(values: &Self::Values<f64>, k: usize) -> Option<String>;
    /// Component `k`'s [`Mechanism::project`].
    fn project(values: &mut Self::Values<f64>, k: usize);
    /// Component `k`'s [`Mechanism::monitor`].
    fn monitor(values: &Self::Values<f64>, k: usize) -> Monitor;
}

impl Components for () {
    type Values<S: Scalar> = ();
    const FIELDS: usize = 0;
    const VARIABLES: usize = 0;
    const PROJECTED: bool = false;
    const MONITORED: bool = false;

    fn zeros<S: Scalar>() {}
    fn map<A: Scalar, B: Scalar>(_: &(), _: &impl Fn(A) -> B) {}
    fn set_time<S: Scalar>(_: &mut (), _: S) {}
    fn field_of(_: usize, _: usize) -> Option<usize> {
        None
    }
    fn reference_at(_: usize, _: usize) -> Option<usize> {
        None
    }
    fn evaluate<S: Scalar>(_: &mut (), _: usize, _: bool) {}
    fn outputs<S: Scalar>(_: &mut (), _: usize) {}
    fn calculate(_: &mut (), _: usize) -> Result<(), String> {
        Ok(())
    }
    fn diagnose(_: &(), _: usize) -> Option<String> {
        None
    }
    fn project(_: &mut (), _: usize) {}
    fn monitor(_: &(), _: usize) -> Monitor {
        Monitor::Valid
    }
}

impl<M: Mechanism, T: Components> Components for (M, T) {
    type Values<S: Scalar> = Pair<M::Values<S>, T::Values<S>>;
    const FIELDS: usize = M::VARIABLES.len() + 1 + T::FIELDS;
    const VARIABLES: usize = M::VARIABLES.len() + T::VARIABLES;
    const PROJECTED: bool = M::PROJECTED || T::PROJECTED;
    const MONITORED: bool = M::MONITORED || T::MONITORED;

    #[inline]
    fn zeros<S: Scalar>() -> Self::Values<S> {
        Pair {
            head: M::zeros(),
            tail: T::zeros(),
        }
    }

    #[inline]
    fn map<A: Scalar, B: Scalar>(values: &Self::Values<A>, f: &impl Fn(A) -> B) -> Self::Values<B> {
        Pair {
            head: M::map_values(&values.head, f),
            tail: T::map(&values.tail, f),
        }
    }

    #[inline(always)]
    fn set_time<S: Scalar>(values: &mut Self::Values<S>, t: S) {
        values.head.set_time(t);
        T::set_time(&mut values.tail, t);
    }

    #[inline(always)]
    fn field_of(vr: usize, first: usize) -> Option<usize> {
        let n = M::VARIABLES.len();
        if vr < n {
            Some(first + 1 + vr)
        } else {
            T::field_of(vr - n, first + 1 + n)
        }
    }

    #[inline(always)]
    fn reference_at(field: usize, first: usize) -> Option<usize> {
        let n = M::VARIABLES.len();
        match field {
            0 => None, // the component's time
            f if f <= n => Some(first + f - 1),
            f => T::reference_at(f - 1 - n, first + n),
        }
    }

    #[inline(always)]
    fn evaluate<S: Scalar>(values: &mut Self::Values<S>, k: usize, outputs: bool) {
        if k == 0 {
            M::evaluate(&mut values.head);
            if outputs {
                M::outputs(&mut values.head);
            }
        } else {
            T::evaluate(&mut values.tail, k - 1, outputs);
        }
    }

    #[inline(always)]
    fn outputs<S: Scalar>(values: &mut Self::Values<S>, k: usize) {
        if k == 0 {
            M::outputs(&mut values.head);
        } else {
            T::outputs(&mut values.tail, k - 1);
        }
    }

    fn calculate(values: &mut Self::Values<f64>, k: usize) -> Result<(), String> {
        match k {
            0 => M::calculate(&mut values.head),
            _ => T::calculate(&mut values.tail, k - 1),
        }
    }

    fn diagnose(values: &Self::Values<f64>, k: usize) -> Option<String> {
        match k {
            0 => M::diagnose(&values.head),
            _ => T::diagnose(&values.tail, k - 1),
        }
    }

    #[inline]
    fn project(values: &mut Self::Values<f64>, k: usize) {
        match k {
            0 if M::PROJECTED => M::project(&mut values.head),
            0 => {}
            _ => T::project(&mut values.tail, k - 1),
        }
    }

    #[inline]
    fn monitor(values: &Self::Values<f64>, k: usize) -> Monitor {
        match k {
            0 if M::MONITORED => M::monitor(&values.head),
            0 => Monitor::Valid,
            _ => T::monitor(&values.tail, k - 1),
        }
    }
}

/// The values of a system whose components are all zero.
pub fn zeros<S: Scalar, L: Components>() -> SystemValues<S, L> {
    SystemValues {
        time: S::zero(),
        components: L::zeros(),
    }
}

/// The values with every field converted by `f`.
pub fn map_values<A: Scalar, B: Scalar, L: Components>(
    values: &SystemValues<A, L>,
    f: impl Fn(A) -> B,
) -> SystemValues<B, L> {
    SystemValues {
        time: f(values.time),
        components: L::map(&values.components, &f),
    }
}
