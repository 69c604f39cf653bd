//! A mechanism's generalized coordinates: declared by name, resolved to value references at
//! compile time, each mistake a compile error naming the coordinate.

use crate::model::{
    closest_name, str_eq, variable_position, Causality, ConstMessage, Variability, Variable,
};

/// A generalized coordinate, named by its position state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Coordinate {
    /// The position state; its derivative is the velocity state, whose derivative is the
    /// acceleration.
    pub name: &'static str,
    /// For a driven coordinate: the output that receives the generalized force its drive
    /// exerts.
    pub drive: Option<&'static str>,
}

impl Coordinate {
    /// A coordinate whose acceleration Lagrange's equations give (written to the velocity
    /// state's derivative, an output or local variable).
    pub const fn free(name: &'static str) -> Self {
        Coordinate { name, drive: None }
    }

    /// A coordinate whose motion is prescribed: its acceleration is an input (the velocity
    /// state's derivative), and `force` is the output that receives the generalized force the
    /// drive exerts to prescribe it (a force for a length, a torque for an angle).
    pub const fn driven(name: &'static str, force: &'static str) -> Self {
        Coordinate {
            name,
            drive: Some(force),
        }
    }
}

/// A coordinate's value references.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Resolved {
    pub position: usize,
    pub velocity: usize,
    pub acceleration: usize,
    /// The driven coordinate's force output; `None` for a free coordinate.
    pub force: Option<usize>,
}

/// The value references of `coordinates` among `variables`. Panics (at compile time, where
/// it is evaluated as a constant) with a message naming the first coordinate declared wrong.
#[doc(hidden)]
pub const fn resolve<const N: usize>(
    variables: &[Variable],
    coordinates: &[Coordinate; N],
) -> [Resolved; N] {
    let unset = Resolved {
        position: 0,
        velocity: 0,
        acceleration: 0,
        force: None,
    };
    let mut out = [unset; N];
    let mut i = 0;
    while i < N {
        match resolve_one(variables, coordinates.as_slice(), i) {
            Ok(resolved) => out[i] = resolved,
            Err(message) => panic!("{}", message.as_str()),
        }
        i += 1;
    }
    out
}

// Constant evaluation, where the message cannot be boxed (and its size costs nothing).
#[allow(clippy::result_large_err)]
const fn resolve_one(
    variables: &[Variable],
    coordinates: &[Coordinate],
    i: usize,
) -> Result<Resolved, ConstMessage> {
    let coordinate = coordinates[i];
    let name = coordinate.name;
    let mut j = 0;
    while j < i {
        if str_eq(coordinates[j].name, name) {
            return Err(*mistake(name).push(" is listed twice"));
        }
        j += 1;
    }
    let Some(position) = variable_position(variables, name) else {
        let mut message = mistake(name);
        message.push(" names no declared variable");
        if let Some(close) = closest_name(variables, name) {
            message.push(" (did you mean ").quoted(close).push("?)");
        }
        return Err(message);
    };
    let Some(velocity_name) = variables[position].derivative else {
        return Err(*mistake(name).push(
            " is not a state: declare it `Variable::state(unit, start, \"<its velocity>\")`",
        ));
    };
    let Some(velocity) = variable_position(variables, velocity_name) else {
        return Err(*mistake(name).push(" has a derivative that names no declared variable"));
    };
    let Some(acceleration_name) = variables[velocity].derivative else {
        return Err(*mistake(name)
            .push(": its velocity ")
            .quoted(velocity_name)
            .push(
            " is not a state: declare it `Variable::state(unit, start, \"<its acceleration>\")`",
        ));
    };
    let Some(acceleration) = variable_position(variables, acceleration_name) else {
        return Err(*mistake(name)
            .push(": its acceleration ")
            .quoted(acceleration_name)
            .push(" names no declared variable"));
    };
    let accelerated = variables[acceleration];
    let force = match coordinate.drive {
        None => {
            if !matches!(accelerated.causality, Causality::Output | Causality::Local)
                || accelerated.derivative.is_some()
            {
                return Err(*mistake(name)
                    .push(" is free, so its acceleration ")
                    .quoted(acceleration_name)
                    .push(" must be an output or local variable (an input makes it driven: `Coordinate::driven`)"));
            }
            None
        }
        Some(force_name) => {
            if !matches!(accelerated.causality, Causality::Input) {
                return Err(*mistake(name)
                    .push(" is driven, so its acceleration ")
                    .quoted(acceleration_name)
                    .push(" must be an input"));
            }
            let Some(force) = variable_position(variables, force_name) else {
                return Err(*mistake(name)
                    .push(": its drive's force ")
                    .quoted(force_name)
                    .push(" names no declared variable"));
            };
            let output = variables[force];
            if !matches!(output.causality, Causality::Output | Causality::Local)
                || !matches!(output.variability, Variability::Continuous)
                || output.derivative.is_some()
            {
                return Err(*mistake(name)
                    .push(": its drive's force ")
                    .quoted(force_name)
                    .push(" must be an output or local variable that is not a state"));
            }
            // The force output is the drive's alone: no coordinate's own variable, no other
            // drive's force (either would be overwritten by the other).
            let mut k = 0;
            while k < coordinates.len() {
                let other = coordinates[k];
                let mut used = false;
                if let Some(other_position) = variable_position(variables, other.name) {
                    used = force == other_position;
                    if let Some(velocity) = variables[other_position].derivative {
                        used = used || str_eq(velocity, force_name);
                        if let Some(v) = variable_position(variables, velocity) {
                            if let Some(acceleration) = variables[v].derivative {
                                used = used || str_eq(acceleration, force_name);
                            }
                        }
                    }
                }
                if let Some(other_force) = other.drive {
                    used = used || (k != i && str_eq(other_force, force_name));
                }
                if used {
                    return Err(*mistake(name)
                        .push(": its drive's force ")
                        .quoted(force_name)
                        .push(" is also coordinate ")
                        .quoted(other.name)
                        .push("'s variable or its drive's force"));
                }
                k += 1;
            }
            Some(force)
        }
    };
    Ok(Resolved {
        position,
        velocity,
        acceleration,
        force,
    })
}

/// The start of the message about coordinate `name`.
const fn mistake(name: &str) -> ConstMessage {
    let mut message = ConstMessage::new();
    message.push("coordinate ").quoted(name);
    message
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_misspelled_coordinate_is_named_with_the_nearest_name() {
        // Two letters swapped is one edit: `tehta` is near `theta`.
        const PENDULUM: &[Variable] = &[
            Variable::state("rad", 0.5, "theta_dot").named("theta", ""),
            Variable::state("rad/s", 0.0, "theta_ddot").named("theta_dot", ""),
            Variable::output("rad/s2").named("theta_ddot", ""),
        ];
        let message = resolve_one(PENDULUM, &[Coordinate::free("tehta")], 0)
            .err()
            .map(|m| m.as_str().to_string());
        assert_eq!(
            message.as_deref(),
            Some("coordinate `tehta` names no declared variable (did you mean `theta`?)")
        );
    }
}
