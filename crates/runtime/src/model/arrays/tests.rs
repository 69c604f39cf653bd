use super::*;

const fn named(v: Variable, name: &'static str) -> Variable {
    v.named(name, "")
}

/// A symmetric matrix of three parameters, an input, two states, their rates, an output.
static VARIABLES: [Variable; 9] = [
    named(Variable::parameter("kg", 1.0).positive(), "m_11"),
    named(Variable::parameter("kg", 0.5), "m_12"),
    named(Variable::parameter("kg", 2.0).positive(), "m_22"),
    named(Variable::input("N", 0.0), "u"),
    named(Variable::state("m", 0.0, "v_1"), "x_1"),
    named(Variable::state("m", 0.0, "v_2"), "x_2"),
    named(Variable::output("m/s"), "v_1"),
    named(Variable::output("m/s"), "v_2"),
    named(Variable::output("J"), "E"),
];

const M: Array = Array::new(
    "M",
    "Mass matrix",
    &[2, 2],
    &["m_11", "m_12", "m_12", "m_22"],
);
const X: Array = Array::new("x", "Positions", &[2], &["x_1", "x_2"]);
const V: Array = Array::new("v", "Velocities", &[2], &["v_1", "v_2"]);

fn shapes(arrays: &'static [Array]) -> Result<Shapes, String> {
    Shapes::new(&VARIABLES, arrays)
}

fn summary(shapes: &Shapes) -> Vec<(usize, &str, Vec<usize>)> {
    (shapes.variables.iter())
        .map(|s| (s.reference, s.name, s.elements.clone()))
        .collect()
}

#[test]
fn without_arrays_every_scalar_is_a_variable() {
    let shapes = shapes(&[]).unwrap();
    assert_eq!(shapes.variables.len(), VARIABLES.len());
    for (vr, s) in shapes.variables.iter().enumerate() {
        assert_eq!((s.reference, s.name), (vr + 1, VARIABLES[vr].name));
        assert_eq!((s.elements.as_slice(), s.is_array()), (&[vr][..], false));
        assert_eq!(shapes.get(vr + 1), Some(s));
        assert_eq!(shapes.owner(vr), Some(s));
    }
    assert!(!shapes.has_arrays());
    // 0 is the time's, and no variable's.
    assert_eq!(Shapes::TIME_REFERENCE, 0);
    assert_eq!(shapes.get(0), None);
    assert_eq!(shapes.references_end(), 10);
    assert_eq!((shapes.get(10), shapes.owner(9)), (None, None));
}

#[test]
fn an_array_stands_at_its_first_element_with_its_reference() {
    let shapes = shapes(&[M, X, V]).unwrap();
    assert_eq!(
        summary(&shapes),
        [
            (1, "M", vec![0, 1, 1, 2]),
            (2, "u", vec![3]),
            (3, "x", vec![4, 5]),
            (4, "v", vec![6, 7]),
            (5, "E", vec![8]),
        ]
    );
    assert!(shapes.has_arrays());
    assert_eq!(shapes.variables[0].dimensions, [2, 2]);
    assert_eq!(shapes.variables[0].description, "Mass matrix");
    // An array is one variable, with one value reference: the next variable's is the next.
    assert_eq!(shapes.get(1).map(|s| s.name), Some("M"));
    assert_eq!(shapes.get(2).map(|s| s.name), Some("u"));
    assert_eq!(shapes.owner(1).map(|s| s.name), Some("M"));
    assert_eq!(shapes.owner(7).map(|s| s.name), Some("v"));
    assert_eq!(shapes.variables[2].variable(&VARIABLES).name, "x_1");
    // Value references are places in the list: 1 to 5, then none.
    assert_eq!((shapes.references_end(), shapes.get(6)), (6, None));
}

/// A prescribed acceleration declared before the states it drives is listed after them
/// (each state before its derivative), and the value references follow the list.
#[test]
fn a_derivative_declared_before_its_state_is_listed_after_it() {
    static DRIVEN: [Variable; 4] = [
        named(Variable::input("m/s2", 0.0), "a"),
        named(Variable::parameter("kg", 1.0), "m"),
        named(Variable::state("m", 0.0, "v"), "x"),
        named(Variable::state("m/s", 0.0, "a"), "v"),
    ];
    let shapes = Shapes::new(&DRIVEN, &[]).unwrap();
    assert_eq!(
        summary(&shapes),
        [
            (1, "x", vec![2]),
            (2, "v", vec![3]),
            (3, "a", vec![0]),
            (4, "m", vec![1])
        ]
    );
    assert_eq!(shapes.owner(0).map(|s| s.reference), Some(3));
    assert_eq!(shapes.get(3).map(|s| s.name), Some("a"));
}

#[test]
fn an_array_may_take_the_name_of_its_own_element() {
    static E: [Array; 1] = [Array::new("E", "Energy", &[1], &["E"])];
    let shapes = shapes(&E).unwrap();
    assert_eq!(
        shapes.get(9).map(|s| (s.name, s.is_array())),
        Some(("E", true))
    );
}

#[test]
fn element_names_are_row_major_and_1_based() {
    let shapes = shapes(&[M, X, V]).unwrap();
    let m = &shapes.variables[0];
    let names: Vec<String> = (0..4).map(|k| m.element_name(k)).collect();
    assert_eq!(names, ["M[1,1]", "M[1,2]", "M[2,1]", "M[2,2]"]);
    assert_eq!(shapes.variables[2].element_name(1), "x[2]");
    assert_eq!(shapes.variables[4].element_name(0), "E");
    let cube = Shaped {
        reference: 0,
        name: "T",
        description: "",
        dimensions: &[2, 3, 4],
        elements: vec![0; 24],
    };
    assert_eq!(cube.element_name(5), "T[1,2,2]");
    assert_eq!(cube.element_name(23), "T[2,3,4]");
}

#[test]
fn refused_arrays_name_the_problem() {
    static CASES: &[(&[Array], &str)] = &[
        (
            &[Array::new("A", "", &[], &[])],
            "array `A` needs dimensions of at least 1",
        ),
        (
            &[Array::new("A", "", &[0], &[])],
            "array `A` needs dimensions of at least 1",
        ),
        (
            &[Array::new("A", "", &[2], &["u", "E", "m_11"])],
            "array `A` of dimensions [2] needs 2 elements, not 3",
        ),
        (
            &[Array::new("A", "", &[usize::MAX, 2], &["u"])],
            "needs too many elements, not 1",
        ),
        (
            &[Array::new("A", "", &[1], &["w"])],
            "array `A`: element `w` is not a declared variable",
        ),
        (
            &[Array::new("E", "", &[1], &["u"])],
            "array `E` has the name of a variable outside it",
        ),
        (
            &[
                Array::new("A", "", &[1], &["u"]),
                Array::new("A", "", &[1], &["E"]),
            ],
            "array `A` is declared twice",
        ),
        (
            &[
                Array::new("A", "", &[1], &["u"]),
                Array::new("B", "", &[2], &["E", "u"]),
            ],
            "`u` is an element of two arrays, `A` and `B`",
        ),
        (
            &[Array::new("A", "", &[2], &["m_11", "u"])],
            "array `A`: `u` differs from `m_11` in unit",
        ),
        (
            &[Array::new("A", "", &[2], &["v_2", "E"])],
            "array `A`: `E` differs from `v_2` in unit",
        ),
        (
            &[X],
            "the derivatives of `x` are not shaped as it is: declare one array",
        ),
        (
            &[X, Array::new("v", "", &[2], &["v_2", "v_1"])],
            "the derivatives of `x` are not shaped as it is",
        ),
        (
            &[X, Array::new("v", "", &[1, 2], &["v_1", "v_2"])],
            "the derivatives of `x` are not shaped as it is",
        ),
        (
            &[V],
            "the derivatives of `x_1` are not shaped as it is: a scalar state's derivative",
        ),
        (
            &[
                Array::new("x", "", &[2], &["x_2", "x_1"]),
                Array::new("v", "", &[2], &["v_2", "v_1"]),
            ],
            "the states, array by array, are not in declaration order",
        ),
    ];
    for &(arrays, expected) in CASES {
        let err = shapes(arrays).expect_err(expected);
        assert!(err.contains(expected), "{expected}: {err}");
    }
}
