//! What the model description and the binary of an FMU must agree on, and the one place
//! each is defined: the capabilities the FMU declares (and the runtime implements), the log
//! categories, and the GUID that ties a `modelDescription.xml` to its binary. The XML
//! writer, the GUID and the FMI layer all read them from here.
//!
//! The GUID is derived from the declaration: the same declaration always gives the same
//! GUID, and any change an importer could see gives another.

use crate::model::Mechanism;

/// The capability flags of the `<CoSimulation>` element, and those of them that
/// `<ModelExchange>` has too. The runtime must do what these promise; [`CAPABILITIES`] is
/// the one place they are set for every FMU.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Capabilities {
    pub needs_execution_tool: bool,
    pub can_handle_variable_communication_step_size: bool,
    pub can_interpolate_inputs: bool,
    pub max_output_derivative_order: u32,
    /// Spelled as in the FMI 2.0 schema (`canRunAsynchronuously`).
    pub can_run_asynchronuously: bool,
    pub can_be_instantiated_only_once_per_process: bool,
    pub can_not_use_memory_management_functions: bool,
    pub can_get_and_set_fmu_state: bool,
    pub can_serialize_fmu_state: bool,
    /// Also decides whether `<ModelStructure>` has `<Derivatives>` and whether dependencies
    /// list the continuous states (FMI 2.0.5, section 2.2.8: both are ignored or absent for
    /// Co-Simulation without directional derivatives).
    pub provides_directional_derivative: bool,
}

impl Capabilities {
    /// Variable communication step sizes, many instances, no memory-management callbacks;
    /// none of the optional capabilities (FMU state, input interpolation, output and
    /// directional derivatives, asynchronous steps).
    pub const NONE: Capabilities = Capabilities {
        needs_execution_tool: false,
        can_handle_variable_communication_step_size: true,
        can_interpolate_inputs: false,
        max_output_derivative_order: 0,
        can_run_asynchronuously: false,
        can_be_instantiated_only_once_per_process: false,
        can_not_use_memory_management_functions: true,
        can_get_and_set_fmu_state: false,
        can_serialize_fmu_state: false,
        provides_directional_derivative: false,
    };

    /// The attributes of `<ModelExchange>` after `modelIdentifier`, in the schema's order.
    /// `completedIntegratorStepNotNeeded` is the mechanism's: true unless something runs
    /// at `fmi2CompletedIntegratorStep`.
    pub(crate) fn model_exchange_attributes(
        &self,
        needs_completed_integrator_step: bool,
    ) -> Vec<(&'static str, String)> {
        let mut attributes = vec![
            ("needsExecutionTool", self.needs_execution_tool.to_string()),
            (
                "completedIntegratorStepNotNeeded",
                (!needs_completed_integrator_step).to_string(),
            ),
        ];
        attributes.extend(self.shared_tail());
        attributes
    }

    /// The attributes of `<CoSimulation>` after `modelIdentifier`, in the schema's order.
    pub(crate) fn attributes(&self) -> Vec<(&'static str, String)> {
        let b = |x: bool| x.to_string();
        let mut attributes = vec![
            ("needsExecutionTool", b(self.needs_execution_tool)),
            (
                "canHandleVariableCommunicationStepSize",
                b(self.can_handle_variable_communication_step_size),
            ),
            ("canInterpolateInputs", b(self.can_interpolate_inputs)),
            (
                "maxOutputDerivativeOrder",
                self.max_output_derivative_order.to_string(),
            ),
            ("canRunAsynchronuously", b(self.can_run_asynchronuously)),
        ];
        attributes.extend(self.shared_tail());
        attributes
    }

    /// The attributes both elements end with, in the schema's order.
    fn shared_tail(&self) -> [(&'static str, String); 5] {
        let b = |x: bool| x.to_string();
        [
            (
                "canBeInstantiatedOnlyOncePerProcess",
                b(self.can_be_instantiated_only_once_per_process),
            ),
            (
                "canNotUseMemoryManagementFunctions",
                b(self.can_not_use_memory_management_functions),
            ),
            ("canGetAndSetFMUstate", b(self.can_get_and_set_fmu_state)),
            ("canSerializeFMUstate", b(self.can_serialize_fmu_state)),
            (
                "providesDirectionalDerivative",
                b(self.provides_directional_derivative),
            ),
        ]
    }
}

/// The capabilities every mechanism's FMU declares: all that the runtime implements
/// (FMU state and its serialization, input interpolation up to order 2 (declared by
/// `canInterpolateInputs`), first output derivatives, exact directional derivatives).
pub const CAPABILITIES: Capabilities = Capabilities {
    can_interpolate_inputs: true,
    max_output_derivative_order: 1,
    can_get_and_set_fmu_state: true,
    can_serialize_fmu_state: true,
    provides_directional_derivative: true,
    ..Capabilities::NONE
};

/// The log categories declared in every modelDescription, with their descriptions.
pub const LOG_CATEGORIES: [(&str, &str); 6] = [
    (
        "logEvents",
        "Initialization, parameter changes and solver statistics",
    ),
    (
        "logStatusWarning",
        "Messages of calls that return fmi2Warning",
    ),
    (
        "logStatusDiscard",
        "Messages of calls that return fmi2Discard",
    ),
    ("logStatusError", "Messages of calls that return fmi2Error"),
    ("logStatusFatal", "Messages of calls that return fmi2Fatal"),
    ("logAll", "All of the above"),
];

/// Bump when the modelDescription generator changes what it writes from the same
/// declaration, so binaries and XML of different generator versions never match.
const GENERATOR_VERSION: &str = "mechfmu-md-3";

/// 64-bit FNV-1a over a stream of fields (each prefixed by its length, so field boundaries
/// count).
struct Fnv(u64);

impl Fnv {
    fn new(seed: u64) -> Self {
        Fnv(0xcbf2_9ce4_8422_2325 ^ seed.wrapping_mul(0x0100_0000_01b3))
    }
    fn bytes(&mut self, b: &[u8]) {
        for &x in (b.len() as u64).to_le_bytes().iter().chain(b) {
            self.0 ^= x as u64;
            self.0 = self.0.wrapping_mul(0x0100_0000_01b3);
        }
    }
    fn f64(&mut self, x: Option<f64>) {
        match x {
            Some(x) => self.bytes(&x.to_bits().to_le_bytes()),
            None => self.bytes(b"-"),
        }
    }
}

fn hash<M: Mechanism>(seed: u64) -> u64 {
    let mut h = Fnv::new(seed);
    h.bytes(GENERATOR_VERSION.as_bytes());
    h.bytes(M::NAME.as_bytes());
    h.bytes(M::DESCRIPTION.as_bytes());
    h.bytes(format!("{:?}", CAPABILITIES).as_bytes());
    let e = M::EXPERIMENT;
    for x in [e.start, e.stop, e.step, e.tolerance] {
        h.f64(Some(x));
    }
    for indicator in M::EVENT_INDICATORS {
        h.bytes(indicator.as_bytes());
    }
    h.bytes(&[M::MONITORED as u8, M::PROJECTED as u8]);
    for v in M::VARIABLES {
        h.bytes(v.name.as_bytes());
        h.bytes(v.description.as_bytes());
        h.bytes(v.causality.as_str().as_bytes());
        h.bytes(v.variability.as_str().as_bytes());
        h.bytes(v.initial.map_or("", |i| i.as_str()).as_bytes());
        h.bytes(v.unit.as_bytes());
        h.f64(v.start);
        h.f64(v.min);
        h.f64(v.max);
        h.bytes(&[v.positive as u8]);
        h.bytes(v.derivative.unwrap_or("").as_bytes());
    }
    h.0
}

/// The GUID, formatted as `{xxxxxxxx-xxxx-xxxx-xxxx-xxxxxxxxxxxx}`.
pub fn guid<M: Mechanism>() -> String {
    let (a, b) = (hash::<M>(1), hash::<M>(2));
    format!(
        "{{{:08x}-{:04x}-{:04x}-{:04x}-{:012x}}}",
        a >> 32,
        (a >> 16) & 0xffff,
        a & 0xffff,
        b >> 48,
        b & 0xffff_ffff_ffff
    )
}
