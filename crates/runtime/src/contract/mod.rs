//! What the model description and the binary of an FMU must agree on, and the one place
//! each is defined: the capabilities the FMU declares (and the runtime implements), the log
//! categories, the GUID that ties a `modelDescription.xml` to its binary (FMI 3.0: the
//! instantiation token), and where each platform's binary is in the archive ([`platform`]).
//! The XML writers, the GUID, the FMI layers, the documentation page and every importer and
//! packager of mechfmu read them from here.
//!
//! The GUID is derived from the declaration: the same declaration always gives the same
//! GUID, and any change an importer could see gives another.

mod capabilities;
pub mod platform;
mod token;

pub use capabilities::{Capabilities, Fmi3Capabilities, CAPABILITIES, FMI3_CAPABILITIES};
pub use token::{guid, instantiation_token};

use crate::model::Mechanism;

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
