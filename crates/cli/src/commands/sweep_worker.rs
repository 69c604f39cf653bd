//! `mechfmu sweep-worker` (hidden): the native engine of `mechfmu sweep`, which its Python
//! side starts once per Dask worker (`mechfmu-sweep-worker`: the protocol, the cases).

use std::process::ExitCode;

/// Serves until the end of stdin; the process's exit status.
pub fn run() -> ExitCode {
    mechfmu_sweep_worker::run()
}
