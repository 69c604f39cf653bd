//! Array variables: declared scalars grouped into the vectors and matrices the physics has
//! (an inertia tensor, a quaternion), as FMI 3.0 shows them. The scalars stay the
//! declaration and the equations' names (and FMI 2.0's variables); an [`Array`] only says
//! which of them make up one array variable of FMI 3.0, in which order.
//!
//! [`Shapes`] is the list of variables FMI 3.0 sees, in the order its model description
//! lists them: every scalar that is in no array, and every array at the place of its first
//! element, each state before its derivative (as FMI 2.0's `ScalarVariable`s). FMI 3.0's value
//! references are the 1-based places in that list; the independent variable `time`, listed
//! after them, is 0 ([`Shapes::TIME_REFERENCE`]), as the Reference-FMUs number it. The
//! standard allows any value references; these are what importers that take FMI 3.0's
//! `derivative` and `dependencies` for 1-based places (FMI 2.0's meaning, OMSimulator's Python
//! API) read right.

use super::const_text::{str_eq, ConstMessage};
use super::{states_before_derivatives, Variable};

/// An array variable made of declared scalar variables.
///
/// ```
/// use mechfmu::model::Array;
/// // A symmetric 2×2 matrix of three scalars: `m_12` stands at two places.
/// const M: Array = Array::new("M", "Mass matrix", &[2, 2], &["m_11", "m_12", "m_12", "m_22"]);
/// assert_eq!(M.len(), 4);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Array {
    pub name: &'static str,
    pub description: &'static str,
    /// The extent of each dimension: `[3]` for a vector, `[3, 3]` for a matrix.
    pub dimensions: &'static [usize],
    /// The scalar variables, in row-major order. A scalar may stand at several places (the
    /// two off-diagonal places of a symmetric matrix): setting the array then requires the
    /// values there to be equal.
    pub elements: &'static [&'static str],
}

impl Array {
    pub const fn new(
        name: &'static str,
        description: &'static str,
        dimensions: &'static [usize],
        elements: &'static [&'static str],
    ) -> Self {
        Array {
            name,
            description,
            dimensions,
            elements,
        }
    }

    /// The number of elements: the product of the dimensions.
    pub const fn len(&self) -> usize {
        let mut n = 1;
        let mut i = 0;
        while i < self.dimensions.len() {
            n *= self.dimensions[i];
            i += 1;
        }
        n
    }

    pub const fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Compile-time check of a mechanism's arrays, run by `export_fmu!`: each element names a
/// declared variable and each array has as many elements as its dimensions say.
/// [`Shapes::new`] checks the rest (units, kinds, states) when the FMU is built and tested.
pub const fn check_arrays(variables: &[Variable], arrays: &[Array]) {
    let mut a = 0;
    while a < arrays.len() {
        let array = &arrays[a];
        let mut m = ConstMessage::new();
        m.push("Mechanism::ARRAYS: array ")
            .quoted(array.name)
            .push(" ");
        if array.dimensions.is_empty() || array.is_empty() {
            m.push("has no dimension, or a dimension of 0");
            panic!("{}", m.as_str());
        }
        if array.len() != array.elements.len() {
            m.push("lists a number of elements its dimensions do not give");
            panic!("{}", m.as_str());
        }
        let mut e = 0;
        while e < array.elements.len() {
            let mut j = 0;
            while j < variables.len() && !str_eq(variables[j].name, array.elements[e]) {
                j += 1;
            }
            if j == variables.len() {
                m.push("names ")
                    .quoted(array.elements[e])
                    .push(" as an element, but no variable has that name");
                panic!("{}", m.as_str());
            }
            e += 1;
        }
        a += 1;
    }
}

/// One variable as FMI 3.0 sees it: a scalar, or an array of scalars.
#[derive(Clone, Debug, PartialEq)]
pub struct Shaped {
    /// Its FMI 3.0 value reference: its place in [`Shapes::variables`], plus one.
    pub reference: usize,
    pub name: &'static str,
    pub description: &'static str,
    /// Empty for a scalar.
    pub dimensions: &'static [usize],
    /// The value references of its scalars, in row-major order (one for a scalar).
    pub elements: Vec<usize>,
}

impl Shaped {
    pub fn is_array(&self) -> bool {
        !self.dimensions.is_empty()
    }

    /// The declaration of its (first) scalar: every element has the same unit, causality,
    /// variability and `initial`.
    pub fn variable<'a>(&self, variables: &'a [Variable]) -> &'a Variable {
        &variables[self.elements[0]]
    }

    /// `name[i,j]` (1-based, as FMI 3.0 and Modelica write an element) of element `k`.
    pub fn element_name(&self, k: usize) -> String {
        if !self.is_array() {
            return self.name.to_string();
        }
        element_name(self.name, self.dimensions, k)
    }
}

/// `name[i,j]` (1-based, as FMI 3.0 and Modelica write an element) of element `k`
/// (row-major) of an array of `dimensions`.
pub fn element_name(name: &str, dimensions: &[usize], k: usize) -> String {
    let mut index = Vec::with_capacity(dimensions.len());
    let mut rest = k;
    for &d in dimensions.iter().rev() {
        index.push(rest % d.max(1) + 1);
        rest /= d.max(1);
    }
    index.reverse();
    let index: Vec<String> = index.iter().map(usize::to_string).collect();
    format!("{name}[{}]", index.join(","))
}

/// The variables of a declaration as FMI 3.0 sees them, with its arrays.
#[derive(Clone, Debug, PartialEq)]
pub struct Shapes {
    /// In the order of the model description: declaration order of each variable's first
    /// scalar, each state before its derivative.
    pub variables: Vec<Shaped>,
    /// For each scalar's value reference, the variable it belongs to (index into `variables`).
    owner: Vec<usize>,
}

impl Shapes {
    /// Groups `variables` into `arrays`; `Err` names the first problem: an element that is
    /// no variable or in two arrays, elements of different units or kinds, an array named
    /// like another variable, a state array whose derivatives are not one array in the same
    /// order, an array of states out of the states' order.
    pub fn new(variables: &'static [Variable], arrays: &'static [Array]) -> Result<Self, String> {
        const NONE: usize = usize::MAX;
        let mut array_of = vec![NONE; variables.len()];
        let mut groups: Vec<Vec<usize>> = Vec::with_capacity(arrays.len());
        for (a, array) in arrays.iter().enumerate() {
            if array.dimensions.is_empty() || array.dimensions.contains(&0) {
                return Err(format!(
                    "array `{}` needs dimensions of at least 1",
                    array.name
                ));
            }
            let len = (array.dimensions.iter()).try_fold(1usize, |n, &d| n.checked_mul(d));
            if len != Some(array.elements.len()) {
                return Err(format!(
                    "array `{}` of dimensions {:?} needs {} elements, not {}",
                    array.name,
                    array.dimensions,
                    len.map_or("too many".into(), |n| n.to_string()),
                    array.elements.len()
                ));
            }
            if let Some(other) = variables.iter().find(|v| v.name == array.name) {
                if !array.elements.contains(&other.name) {
                    return Err(format!(
                        "array `{}` has the name of a variable outside it",
                        array.name
                    ));
                }
            }
            if arrays[..a].iter().any(|b| b.name == array.name) {
                return Err(format!("array `{}` is declared twice", array.name));
            }
            let mut elements = Vec::with_capacity(array.elements.len());
            for name in array.elements {
                let Some(vr) = variables.iter().position(|v| v.name == *name) else {
                    return Err(format!(
                        "array `{}`: element `{name}` is not a declared variable",
                        array.name
                    ));
                };
                if array_of[vr] != NONE && array_of[vr] != a {
                    return Err(format!(
                        "`{name}` is an element of two arrays, `{}` and `{}`",
                        arrays[array_of[vr]].name, array.name
                    ));
                }
                array_of[vr] = a;
                let (first, v) = (
                    &variables[elements.first().copied().unwrap_or(vr)],
                    &variables[vr],
                );
                let same = first.unit == v.unit
                    && first.causality == v.causality
                    && first.variability == v.variability
                    && first.effective_initial() == v.effective_initial()
                    && first.is_state() == v.is_state();
                if !same {
                    return Err(format!(
                        "array `{}`: `{name}` differs from `{}` in unit, causality, variability, initial or being a state",
                        array.name, first.name
                    ));
                }
                elements.push(vr);
            }
            groups.push(elements);
        }

        let mut shapes = Shapes {
            variables: Vec::new(),
            owner: vec![NONE; variables.len()],
        };
        for (vr, v) in variables.iter().enumerate() {
            let a = array_of[vr];
            if a == NONE {
                shapes.owner[vr] = shapes.variables.len();
                shapes.variables.push(Shaped {
                    reference: 0,
                    name: v.name,
                    description: v.description(),
                    dimensions: &[],
                    elements: vec![vr],
                });
            } else if shapes.owner[vr] == NONE {
                // The array's first element in declaration order: the array stands here.
                let index = shapes.variables.len();
                for &e in &groups[a] {
                    shapes.owner[e] = index;
                }
                shapes.variables.push(Shaped {
                    reference: 0,
                    name: arrays[a].name,
                    description: arrays[a].description,
                    dimensions: arrays[a].dimensions,
                    elements: groups[a].clone(),
                });
            }
        }
        shapes.check_states(variables)?;
        shapes.list_states_before_derivatives(variables);
        Ok(shapes)
    }

    /// Puts the variables in the model description's order (each state before its
    /// derivative, [`states_before_derivatives`]) and numbers them: `time` is 0, the first
    /// variable 1.
    fn list_states_before_derivatives(&mut self, variables: &[Variable]) {
        let order = states_before_derivatives(self.variables.len(), |i| {
            let v = self.variables[i].variable(variables);
            (variables.iter())
                .position(|w| w.derivative == Some(v.name))
                .map(|state| self.owner[state])
        });
        let mut place = vec![0; order.len()];
        for (at, &i) in order.iter().enumerate() {
            place[i] = at;
        }
        let mut listed: Vec<Option<Shaped>> = self.variables.drain(..).map(Some).collect();
        self.variables = (order.iter())
            .map(|&i| listed[i].take().expect("an order lists each variable once"))
            .collect();
        for owner in &mut self.owner {
            *owner = place[*owner];
        }
        for (at, shaped) in self.variables.iter_mut().enumerate() {
            shaped.reference = at + 1;
        }
    }

    /// A state's derivative must be shaped as the state: a scalar state's a scalar, a state
    /// array's one array of the derivatives of its elements, in the same order. And the
    /// states, taken variable by variable and element by element, must be in declaration
    /// order: that is the order of FMI 3.0's continuous-state vector, which is FMI 2.0's.
    fn check_states(&self, variables: &[Variable]) -> Result<(), String> {
        let mut flattened = Vec::new();
        for shaped in &self.variables {
            let v = shaped.variable(variables);
            let Some(_) = v.derivative else { continue };
            let derivatives: Vec<usize> = shaped
                .elements
                .iter()
                .map(|&e| {
                    let name = variables[e].derivative.unwrap_or_default();
                    variables
                        .iter()
                        .position(|w| w.name == name)
                        .unwrap_or(usize::MAX)
                })
                .collect();
            let Some(&first) = derivatives.first().filter(|&&d| d != usize::MAX) else {
                return Err(format!(
                    "state `{}` has no declared derivative",
                    shaped.name
                ));
            };
            let owner = &self.variables[self.owner[first]];
            if owner.elements != derivatives || owner.dimensions != shaped.dimensions {
                return Err(format!(
                    "the derivatives of `{}` are not shaped as it is: {}",
                    shaped.name,
                    if shaped.is_array() {
                        "declare one array of its elements' derivatives, in the same order"
                    } else {
                        "a scalar state's derivative must not be an array element"
                    }
                ));
            }
            flattened.extend(shaped.elements.iter().copied());
        }
        if flattened.windows(2).any(|w| w[0] >= w[1]) {
            return Err(
                "the states, array by array, are not in declaration order: declare each state array's elements together, in the array's order".into(),
            );
        }
        Ok(())
    }

    /// The value reference of the independent variable `time` in FMI 3.0.
    pub const TIME_REFERENCE: usize = 0;

    /// The variable with FMI 3.0 value reference `reference` (none for `time`, nor for a
    /// value reference of no variable).
    pub fn get(&self, reference: usize) -> Option<&Shaped> {
        self.variables.get(reference.checked_sub(1)?)
    }

    /// The variable declared scalar `vr` (FMI 2.0's value reference) belongs to.
    pub fn owner(&self, vr: usize) -> Option<&Shaped> {
        self.owner.get(vr).map(|&i| &self.variables[i])
    }

    /// One past the largest FMI 3.0 value reference: the first that is no variable.
    pub fn references_end(&self) -> usize {
        self.variables.len() + 1
    }

    /// Whether any variable is an array.
    pub fn has_arrays(&self) -> bool {
        self.variables.iter().any(Shaped::is_array)
    }
}

#[cfg(test)]
mod tests;
