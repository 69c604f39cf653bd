//! One module per subcommand, named after it: its arguments (clap) and what it does.

pub mod bench;
pub mod build;
pub mod docs;
pub mod inspect;
pub mod list;
pub mod new;
pub mod sweep;
pub mod sweep_worker;
pub mod validate;
