//! The values of a mechanism by value reference: the one place that reads the named fields
//! `mechanism!` declares (and a system's values, made of them) as the array they are laid
//! out as.

use super::Scalar;
use std::mem::{align_of, size_of};

/// A `#[repr(C)]` struct of `LEN` fields, all of type `S`: the values struct `mechanism!`
/// declares (the time, then one field per variable in value-reference order).
///
/// # Safety
/// Implement it only for a `#[repr(C)]` struct whose `LEN` fields all have type `S`: the
/// runtime reads and writes the struct as `[S; LEN]`. `mechanism!` implements it for the
/// struct it declares, and checks there at compile time that every field is an `S`; a crate
/// that forbids unsafe code cannot implement it by hand, and no crate can without `unsafe`:
///
/// ```compile_fail
/// struct NotScalars {
///     time: f64,
///     boxed: Box<u64>,
/// }
/// impl mechfmu::model::Fields<f64> for NotScalars {
///     const LEN: usize = 2;
/// }
/// ```
#[doc(hidden)]
pub unsafe trait Fields<S: Scalar>: Sized {
    /// The number of fields: the variables plus the time (plus, for a system, each
    /// component's own time).
    const LEN: usize;

    /// The field holding value reference `vr`, or `None` when `vr` is not a variable: the
    /// one after the time, as `mechanism!` lays them out. A system's values, its components'
    /// one after the other, say otherwise. (A field out of range is a panic, never a read.)
    #[inline(always)]
    fn field_of(vr: usize) -> Option<usize> {
        if vr < Self::LEN - 1 {
            Some(vr + 1)
        } else {
            None
        }
    }

    /// The value reference `field` holds, or `None` for a time: the inverse of
    /// [`Fields::field_of`].
    #[inline(always)]
    fn reference_at(field: usize) -> Option<usize> {
        field.checked_sub(1).filter(|&vr| vr < Self::LEN - 1)
    }
}

/// `V` has exactly the size and alignment of `[S; LEN]`: no padding, nothing but its
/// fields. Evaluated at compile time for every scalar type the values are used with.
const fn assert_laid_out_as_array<S: Scalar, V: Fields<S>>() {
    assert!(
        size_of::<V>() == V::LEN * size_of::<S>() && align_of::<V>() == align_of::<S>(),
        "a values struct must be LEN fields of its scalar type, nothing else"
    )
}

/// The fields of `values` as a slice, field `i` at index `i`.
#[inline(always)]
fn fields<S: Scalar, V: Fields<S>>(values: &V) -> &[S] {
    const { assert_laid_out_as_array::<S, V>() };
    // SAFETY: `V` is a repr(C) struct of `LEN` fields of type `S` (the contract of
    // `Fields`), and has exactly the size and alignment of `[S; LEN]` (checked above, at
    // compile time, for every scalar type it is used with): no padding, field `i` at offset
    // `i * size_of::<S>()`, as in the array. The borrow of the slice is the borrow of `values`.
    unsafe { std::slice::from_raw_parts(values as *const V as *const S, V::LEN) }
}

/// As [`fields`], mutably.
#[inline(always)]
fn fields_mut<S: Scalar, V: Fields<S>>(values: &mut V) -> &mut [S] {
    const { assert_laid_out_as_array::<S, V>() };
    // SAFETY: as in `fields`; the borrow is exclusive.
    unsafe { std::slice::from_raw_parts_mut(values as *mut V as *mut S, V::LEN) }
}

/// Value reference `vr`'s value (the field after the time), or `None` when `vr` is not a
/// variable. O(1): an index, not a search.
#[inline(always)]
pub fn get<S: Scalar, V: Fields<S>>(values: &V, vr: usize) -> Option<S> {
    V::field_of(vr).map(|i| fields(values)[i])
}

/// Sets value reference `vr`; false when `vr` is not a variable.
#[inline(always)]
pub fn set<S: Scalar, V: Fields<S>>(values: &mut V, vr: usize, value: S) -> bool {
    match V::field_of(vr) {
        Some(i) => {
            fields_mut(values)[i] = value;
            true
        }
        None => false,
    }
}

/// The value reference of the field `field` refers to, if it is one of `values`' variables.
pub fn reference_of<S: Scalar, V: Fields<S>>(values: &V, field: &S) -> Option<usize> {
    let position = fields(values).iter().position(|f| std::ptr::eq(f, field))?;
    V::reference_at(position)
}

/// The values of `vrs` into `to`, each by an 8-byte load of its own (volatile: the compiler
/// neither merges nor vectorizes them). Values stored one by one just before (by another
/// call) are then forwarded from the stores, where a wider load across two of them would
/// wait for them to reach the cache.
#[doc(hidden)]
#[inline(always)]
pub fn get_one_by_one<V: Fields<f64>>(values: &V, vrs: &[usize], to: &mut [f64]) {
    let fields = fields(values);
    for (t, &vr) in to.iter_mut().zip(vrs) {
        let field = &fields[V::field_of(vr).unwrap_or(usize::MAX)];
        // SAFETY: a reference to an initialized f64 of the values (bounds-checked index).
        *t = unsafe { std::ptr::read_volatile(field) };
    }
}

/// `from` into `to`, one 8-byte load per value, as [`get_one_by_one`]: for arrays an
/// importer has just written one value at a time.
#[doc(hidden)]
#[inline(always)]
pub fn copy_one_by_one(from: &[f64], to: &mut [f64]) {
    for (t, f) in to.iter_mut().zip(from) {
        // SAFETY: a reference to an initialized f64.
        *t = unsafe { std::ptr::read_volatile(f) };
    }
}
