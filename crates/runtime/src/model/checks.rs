//! The checks of a declaration that run at compile time (`mechanism!` for each variable,
//! `export_fmu!` for the event indicators), with messages that name the variable and what
//! is wrong with it; [`Layout::new`](super::Layout::new) gives the same messages at run time.

use super::const_text::{str_eq, ConstMessage};
use super::units::base_units;
use super::{Variability, Variable};

/// Compile-time check of a declaration: [`check_variable`] for each variable.
pub const fn check_declaration(variables: &[Variable]) {
    let mut i = 0;
    while i < variables.len() {
        check_variable(variables, i, "");
        i += 1;
    }
}

/// Compile-time check of variable `index` of a declaration: panics with its
/// [`declaration_error`].
pub const fn check_variable(variables: &[Variable], index: usize, declaration: &str) {
    if let Some(error) = declaration_error(variables, index, declaration) {
        panic!("{}", error.as_str());
    }
}

/// The compile error `mechanism!` reports for variable `index` (reported at that variable's
/// line): its [`variable_mistake`], after `mechanism!: `. `declaration` is the variable's
/// declaration as written, quoted by the messages about its bounds.
pub const fn declaration_error(
    variables: &[Variable],
    index: usize,
    declaration: &str,
) -> Option<ConstMessage> {
    match variable_mistake(variables, index, declaration) {
        Some(mistake) => {
            let mut error = ConstMessage::new();
            error.push("mechanism!: ").push(mistake.as_str());
            Some(error)
        }
        None => None,
    }
}

/// What is wrong with variable `index` of a declaration, in words that name it: its unit
/// does not parse, it is a state whose derivative is not another continuous variable or is
/// an earlier state's too, or its start value or a bound is not finite, or the start value
/// lies outside its bounds. (A name declared twice is a field
/// declared twice, which rustc reports.)
pub const fn variable_mistake(
    variables: &[Variable],
    index: usize,
    declaration: &str,
) -> Option<ConstMessage> {
    let v = &variables[index];
    let mut m = ConstMessage::new();
    if let Err(error) = base_units(v.unit) {
        m.push("variable ").quoted(v.name).push(": ");
        error.describe(v.unit, &mut m);
        return Some(m);
    }
    if let Some(derivative) = v.derivative {
        m.push("state ").quoted(v.name).push(" names ");
        match position(variables, derivative) {
            None => {
                m.quoted(derivative)
                    .push(" as its derivative, but no variable has that name");
                if let Some(close) = closest_name_but(variables, derivative, v.name) {
                    m.push(" (did you mean ").quoted(close).push("?)");
                }
                return Some(m);
            }
            Some(d) if d == index => {
                m.push("itself as its derivative");
                return Some(m);
            }
            Some(d) if !matches!(variables[d].variability, Variability::Continuous) => {
                m.quoted(derivative)
                    .push(" as its derivative, but ")
                    .quoted(derivative)
                    .push(" is a ")
                    .push(variables[d].causality.as_str())
                    .push(", not a continuous variable");
                return Some(m);
            }
            Some(d) => {
                if let Some(other) = earlier_state_with_derivative(variables, index, d) {
                    m.quoted(derivative)
                        .push(" as its derivative, but ")
                        .quoted(derivative)
                        .push(" is already the derivative of ")
                        .quoted(other);
                    return Some(m);
                }
                m = ConstMessage::new();
            }
        }
    }
    let bound = match (v.start, v.min, v.max) {
        (Some(start), _, _) if !start.is_finite() => "its start value is not a finite number",
        (_, Some(min), _) if !min.is_finite() => "its minimum is not a finite number",
        (_, _, Some(max)) if !max.is_finite() => "its maximum is not a finite number",
        (_, Some(min), Some(max)) if min > max => "its minimum is above its maximum",
        (Some(start), Some(min), _) if v.positive && start <= min => {
            "its start value is not > 0, as `.positive()` requires"
        }
        (Some(start), Some(min), _) if start < min => "its start value is below its minimum",
        (Some(start), _, Some(max)) if start > max => "its start value is above its maximum",
        _ => return None,
    };
    m.push("variable ").quoted(v.name).push(": ").push(bound);
    if !declaration.is_empty() {
        m.push(" (declared ").quoted(declaration).push(")");
    }
    Some(m)
}

/// The name of a state declared before variable `index` whose derivative is variable
/// `derivative`, if there is one.
const fn earlier_state_with_derivative(
    variables: &[Variable],
    index: usize,
    derivative: usize,
) -> Option<&'static str> {
    let mut i = 0;
    while i < index {
        if let Some(name) = variables[i].derivative {
            if str_eq(name, variables[derivative].name) {
                return Some(variables[i].name);
            }
        }
        i += 1;
    }
    None
}

/// The position of the variable called `name`.
pub(crate) const fn position(variables: &[Variable], name: &str) -> Option<usize> {
    let mut i = 0;
    while i < variables.len() {
        if str_eq(variables[i].name, name) {
            return Some(i);
        }
        i += 1;
    }
    None
}

/// The declared name nearest to a misspelled `name` (at most a third of its letters, and
/// at least one, changed, added, removed or swapped with its neighbour), if one is.
pub(crate) const fn closest_name(variables: &[Variable], name: &str) -> Option<&'static str> {
    closest_name_but(variables, name, "")
}

/// As [`closest_name`], never proposing `excluded` (a state's own name for its derivative:
/// a state cannot be its own derivative).
pub(crate) const fn closest_name_but(
    variables: &[Variable],
    name: &str,
    excluded: &str,
) -> Option<&'static str> {
    let limit = if name.len() / 3 > 1 {
        name.len() / 3
    } else {
        1
    };
    let mut best: Option<(&'static str, usize)> = None;
    let mut i = 0;
    while i < variables.len() {
        if str_eq(variables[i].name, excluded) {
            i += 1;
            continue;
        }
        if let Some(d) = edit_distance(variables[i].name, name) {
            let better = match best {
                Some((_, best_distance)) => d < best_distance,
                None => true,
            };
            if d <= limit && better {
                best = Some((variables[i].name, d));
            }
        }
        i += 1;
    }
    match best {
        Some((close, _)) => Some(close),
        None => None,
    }
}

/// The Levenshtein distance between two names of up to 63 bytes (`None` for longer ones).
pub(crate) const fn edit_distance(a: &str, b: &str) -> Option<usize> {
    const MAX: usize = 64;
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() >= MAX || b.len() >= MAX {
        return None;
    }
    // Rows i-2, i-1 and i of the distance table (optimal string alignment: a swap of two
    // neighbouring letters is one edit, as in `tehta` for `theta`).
    let mut before = [0usize; MAX];
    let mut previous = [0usize; MAX];
    let mut current = [0usize; MAX];
    let mut j = 0;
    while j <= b.len() {
        previous[j] = j;
        j += 1;
    }
    let mut i = 1;
    while i <= a.len() {
        current[0] = i;
        let mut j = 1;
        while j <= b.len() {
            let substitution = previous[j - 1] + if a[i - 1] == b[j - 1] { 0 } else { 1 };
            let deletion = previous[j] + 1;
            let insertion = current[j - 1] + 1;
            let mut d = substitution;
            if deletion < d {
                d = deletion;
            }
            if insertion < d {
                d = insertion;
            }
            if i > 1
                && j > 1
                && a[i - 1] == b[j - 2]
                && a[i - 2] == b[j - 1]
                && before[j - 2] + 1 < d
            {
                d = before[j - 2] + 1;
            }
            current[j] = d;
            j += 1;
        }
        before = previous;
        previous = current;
        i += 1;
    }
    Some(previous[b.len()])
}

/// Compile-time check of a mechanism's event indicators, run by `export_fmu!`: each names a
/// declared continuous variable, once.
pub const fn check_event_indicators(variables: &[Variable], indicators: &[&str]) {
    let mut k = 0;
    while k < indicators.len() {
        let mut m = ConstMessage::new();
        m.push("Mechanism::EVENT_INDICATORS: ")
            .quoted(indicators[k]);
        match position(variables, indicators[k]) {
            None => {
                m.push(" names no declared variable");
                panic!("{}", m.as_str());
            }
            Some(j) if !matches!(variables[j].variability, Variability::Continuous) => {
                m.push(" is not a continuous variable");
                panic!("{}", m.as_str());
            }
            Some(_) => {}
        }
        let mut i = 0;
        while i < k {
            if str_eq(indicators[i], indicators[k]) {
                m.push(" is listed twice");
                panic!("{}", m.as_str());
            }
            i += 1;
        }
        k += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const CART: &[Variable] = &[
        Variable::parameter("kg", 1.0).named("m", ""),
        Variable::state("m", 0.0, "x_dot").named("x", ""),
        Variable::state("m/s", 0.0, "x_dddot").named("x_dot", ""),
        Variable::output("m/s2").named("x_ddot", ""),
        Variable::state("m", 0.0, "velocity").named("y", ""),
    ];

    fn mistake(index: usize) -> Option<String> {
        variable_mistake(CART, index, "").map(|m| m.as_str().to_string())
    }

    #[test]
    fn a_misspelled_derivative_is_named_with_the_nearest_name() {
        assert_eq!(mistake(0), None);
        assert_eq!(mistake(1), None);
        assert_eq!(
            mistake(2).as_deref(),
            Some("state `x_dot` names `x_dddot` as its derivative, but no variable has that name (did you mean `x_ddot`?)")
        );
        // nothing near enough to suggest
        assert_eq!(
            mistake(4).as_deref(),
            Some("state `y` names `velocity` as its derivative, but no variable has that name")
        );
    }

    #[test]
    fn the_nearest_name_of_a_derivative_is_never_the_state_itself() {
        // `r_ddt` is one edit from both `r_dot` (the state) and `r_ddot`.
        const SPRING: &[Variable] = &[
            Variable::state("m", 1.0, "r_dot").named("r", ""),
            Variable::state("m/s", 0.0, "r_ddt").named("r_dot", ""),
            Variable::output("m/s2").named("r_ddot", ""),
        ];
        let mistake = variable_mistake(SPRING, 1, "").map(|m| m.as_str().to_string());
        assert_eq!(
            mistake.as_deref(),
            Some("state `r_dot` names `r_ddt` as its derivative, but no variable has that name (did you mean `r_ddot`?)")
        );
    }

    #[test]
    fn edit_distances() {
        assert_eq!(edit_distance("x_ddot", "x_dddot"), Some(1));
        assert_eq!(edit_distance("theta", "thetta"), Some(1));
        assert_eq!(edit_distance("theta", "tehta"), Some(1));
        assert_eq!(edit_distance("ab", "ba"), Some(1));
        assert_eq!(edit_distance("abc", "ca"), Some(3));
        assert_eq!(edit_distance("", "abc"), Some(3));
        assert_eq!(edit_distance("kitten", "sitting"), Some(3));
        assert_eq!(edit_distance(&"a".repeat(64), "a"), None);
    }

    fn panic_message(f: impl FnOnce() + std::panic::UnwindSafe) -> String {
        let payload = std::panic::catch_unwind(f).expect_err("the check passed");
        payload
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_default()
    }

    #[test]
    fn event_indicators_are_named_in_their_messages() {
        let vars = &CART[..4];
        check_event_indicators(vars, &["x", "x_ddot"]);
        assert_eq!(
            panic_message(|| check_event_indicators(vars, &["x", "T"])),
            "Mechanism::EVENT_INDICATORS: `T` names no declared variable"
        );
        assert_eq!(
            panic_message(|| check_event_indicators(vars, &["m"])),
            "Mechanism::EVENT_INDICATORS: `m` is not a continuous variable"
        );
        assert_eq!(
            panic_message(|| check_event_indicators(vars, &["x", "x"])),
            "Mechanism::EVENT_INDICATORS: `x` is listed twice"
        );
    }
}
