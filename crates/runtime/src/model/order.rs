//! The order the model descriptions list the variables in (FMI 2.0's `ScalarVariable`s,
//! FMI 3.0's variables, whose value references follow it).

/// The order to list `n` variables in so that each state comes before its derivative:
/// declaration order, but a variable that is the derivative of a state declared after it
/// (`state_of(i)`, the variable `i` is the derivative of) comes right after that state,
/// which comes after its own state the same way. Both standards allow any order (a
/// variable's `derivative` names its state wherever it stands: FMI 2.0.5 section 2.2.7,
/// FMI 3.0 section 2.4.7.5), but importers that resolve `derivative` while they read the
/// variables (OMSimulator's Python API) need the state read first.
pub(crate) fn states_before_derivatives(
    n: usize,
    state_of: impl Fn(usize) -> Option<usize>,
) -> Vec<usize> {
    let mut written = vec![false; n];
    let mut order = Vec::with_capacity(n);
    for i in 0..n {
        // `i`, its state, that state's state, ... up to one written already.
        let mut chain = Vec::new();
        let mut next = Some(i);
        while let Some(j) = next.filter(|&j| !written[j] && !chain.contains(&j)) {
            chain.push(j);
            next = state_of(j);
        }
        for &j in chain.iter().rev() {
            written[j] = true;
            order.push(j);
        }
    }
    order
}
