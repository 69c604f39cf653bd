//! What the model description and the binary of an FMU must agree on, and the one place
//! each is defined: the capabilities the FMU declares (and the runtime implements), the log
//! categories, and the GUID that ties a `modelDescription.xml` to its binary (FMI 3.0: the
//! instantiation token). The XML writers, the GUID and the FMI layers all read them from
//! here.
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

/// The capability flags of FMI 3.0's `<ModelExchange>` and `<CoSimulation>` that the runtime
/// decides, for every FMU; [`FMI3_CAPABILITIES`] is the one place they are set. Two more
/// flags are the mechanism's: [`needs_completed_integrator_step`] and
/// [`might_return_early_from_do_step`]. Flags not here are written nowhere and so take the
/// schema's default `false` (FMI 3.0, section 2.4.2): no execution tool, many instances per
/// process, no per-element dependencies, no `fmi3EvaluateDiscreteStates`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Fmi3Capabilities {
    pub can_get_and_set_fmu_state: bool,
    /// Requires `can_get_and_set_fmu_state`.
    pub can_serialize_fmu_state: bool,
    /// `fmi3GetDirectionalDerivative`.
    pub provides_directional_derivatives: bool,
    /// `fmi3GetAdjointDerivative`.
    pub provides_adjoint_derivatives: bool,
    pub can_handle_variable_communication_step_size: bool,
    /// `fmi3GetOutputDerivatives` up to this order.
    pub max_output_derivative_order: u32,
    /// Intermediate Update Mode (the `intermediateUpdate` callback) in Co-Simulation.
    pub provides_intermediate_update: bool,
    /// Requires `provides_intermediate_update`.
    pub can_return_early_after_intermediate_update: bool,
    /// Co-Simulation's Event Mode, when the importer asks for it at instantiation.
    pub has_event_mode: bool,
}

impl Fmi3Capabilities {
    /// The attributes of `<ModelExchange>` after `modelIdentifier`, in the schema's order
    /// (`fmi3InterfaceType`'s, then `fmi3ModelExchange`'s).
    pub(crate) fn model_exchange_attributes(
        &self,
        needs_completed_integrator_step: bool,
    ) -> Vec<(&'static str, String)> {
        let mut attributes = self.shared_head();
        attributes.push((
            "needsCompletedIntegratorStep",
            needs_completed_integrator_step.to_string(),
        ));
        attributes
    }

    /// The attributes of `<CoSimulation>` after `modelIdentifier`, in the schema's order
    /// (`fmi3InterfaceType`'s, then `fmi3CoSimulation`'s).
    pub(crate) fn co_simulation_attributes(
        &self,
        might_return_early_from_do_step: bool,
    ) -> Vec<(&'static str, String)> {
        let b = |x: bool| x.to_string();
        let mut attributes = self.shared_head();
        attributes.extend([
            (
                "canHandleVariableCommunicationStepSize",
                b(self.can_handle_variable_communication_step_size),
            ),
            (
                "maxOutputDerivativeOrder",
                self.max_output_derivative_order.to_string(),
            ),
            (
                "providesIntermediateUpdate",
                b(self.provides_intermediate_update),
            ),
            (
                "mightReturnEarlyFromDoStep",
                b(might_return_early_from_do_step),
            ),
            (
                "canReturnEarlyAfterIntermediateUpdate",
                b(self.can_return_early_after_intermediate_update),
            ),
            ("hasEventMode", b(self.has_event_mode)),
        ]);
        attributes
    }

    /// The attributes of `fmi3InterfaceType` both elements start with, spelled as the schema
    /// spells them (`canGetAndSetFMUState`, `providesDirectionalDerivatives`).
    fn shared_head(&self) -> Vec<(&'static str, String)> {
        let b = |x: bool| x.to_string();
        vec![
            ("canGetAndSetFMUState", b(self.can_get_and_set_fmu_state)),
            ("canSerializeFMUState", b(self.can_serialize_fmu_state)),
            (
                "providesDirectionalDerivatives",
                b(self.provides_directional_derivatives),
            ),
            (
                "providesAdjointDerivatives",
                b(self.provides_adjoint_derivatives),
            ),
        ]
    }
}

/// The FMI 3.0 capabilities every mechanism's FMU declares: what the runtime implements
/// (FMU state and its serialization, exact directional and adjoint derivatives, first
/// output derivatives, variable communication steps, Co-Simulation's Event Mode); no
/// Intermediate Update Mode.
pub const FMI3_CAPABILITIES: Fmi3Capabilities = Fmi3Capabilities {
    can_get_and_set_fmu_state: true,
    can_serialize_fmu_state: true,
    provides_directional_derivatives: true,
    provides_adjoint_derivatives: true,
    can_handle_variable_communication_step_size: true,
    max_output_derivative_order: 1,
    provides_intermediate_update: false,
    can_return_early_after_intermediate_update: false,
    has_event_mode: true,
};

/// Whether Model Exchange needs `fmi2CompletedIntegratorStep` / `fmi3CompletedIntegratorStep`:
/// when the mechanism's monitor or projection runs there.
pub fn needs_completed_integrator_step<M: Mechanism>() -> bool {
    M::MONITORED || M::PROJECTED
}

/// Whether FMI 3.0's `fmi3DoStep` may return early: at the events of the mechanism's event
/// indicators, where its monitor's verdict changes.
pub fn might_return_early_from_do_step<M: Mechanism>() -> bool {
    !M::EVENT_INDICATORS.is_empty()
}

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

/// [`LOG_CATEGORIES`] with the statuses named as FMI 3.0 names them (`fmi3Warning`, ...):
/// the same categories, for the FMI 3.0 model description.
pub fn fmi3_log_categories() -> Vec<(&'static str, String)> {
    LOG_CATEGORIES
        .iter()
        .map(|&(name, description)| (name, description.replace("fmi2", "fmi3")))
        .collect()
}

/// Bump when the modelDescription generator changes what it writes from the same
/// declaration, so binaries and XML of different generator versions never match.
const GENERATOR_VERSION: &str = "mechfmu-md-3";

/// The same for what only the FMI 3.0 model description writes (the arrays, the
/// independent variable, the FMI 3.0 model structure).
const FMI3_GENERATOR_VERSION: &str = "mechfmu-md3-1";

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
    declaration_hash::<M>(Fnv::new(seed)).0
}

/// The stream of everything FMI 2.0's model description is written from.
fn declaration_hash<M: Mechanism>(mut h: Fnv) -> Fnv {
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
    h
}

/// The stream of everything FMI 3.0's model description is written from: FMI 2.0's, the
/// FMI 3.0 capabilities and the arrays.
fn fmi3_hash<M: Mechanism>(seed: u64) -> u64 {
    let mut h = declaration_hash::<M>(Fnv::new(seed));
    h.bytes(FMI3_GENERATOR_VERSION.as_bytes());
    h.bytes(format!("{:?}", FMI3_CAPABILITIES).as_bytes());
    for array in M::ARRAYS {
        h.bytes(array.name.as_bytes());
        h.bytes(array.description.as_bytes());
        for &d in array.dimensions {
            h.bytes(&(d as u64).to_le_bytes());
        }
        for element in array.elements {
            h.bytes(element.as_bytes());
        }
    }
    h.0
}

/// The GUID, formatted as `{xxxxxxxx-xxxx-xxxx-xxxx-xxxxxxxxxxxx}`.
pub fn guid<M: Mechanism>() -> String {
    braced_uuid(hash::<M>(1), hash::<M>(2))
}

/// FMI 3.0's `instantiationToken`, as [`guid`] but over what FMI 3.0's model description
/// is written from (arrays too), so it differs from the GUID: an FMI 2.0 model description
/// never matches an FMI 3.0 binary call, nor the other way round.
pub fn instantiation_token<M: Mechanism>() -> String {
    braced_uuid(fmi3_hash::<M>(3), fmi3_hash::<M>(4))
}

fn braced_uuid(a: u64, b: u64) -> String {
    format!(
        "{{{:08x}-{:04x}-{:04x}-{:04x}-{:012x}}}",
        a >> 32,
        (a >> 16) & 0xffff,
        a & 0xffff,
        b >> 48,
        b & 0xffff_ffff_ffff
    )
}

/// An FMI version: of an FMU, of the instance an importer made.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Version {
    Fmi2,
    Fmi3,
}

impl Version {
    /// What ties its model description to the binary: FMI 2.0's GUID, FMI 3.0's
    /// instantiation token.
    pub fn token<M: Mechanism>(self) -> String {
        match self {
            Version::Fmi2 => guid::<M>(),
            Version::Fmi3 => instantiation_token::<M>(),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Version::Fmi2 => "FMI 2.0",
            Version::Fmi3 => "FMI 3.0",
        }
    }

    /// The prefix of its functions' names.
    pub fn prefix(self) -> &'static str {
        match self {
            Version::Fmi2 => "fmi2",
            Version::Fmi3 => "fmi3",
        }
    }
}
