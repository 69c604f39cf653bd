//! The capability flags each FMI version's model description declares, set once for every
//! FMU: what the runtime implements.

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
/// flags are the mechanism's: [`needs_completed_integrator_step`](super::needs_completed_integrator_step) and
/// [`might_return_early_from_do_step`](super::might_return_early_from_do_step). Flags not here are written nowhere and so take the
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
