//! One module per subcommand.

pub mod bench;
pub mod experiment;
pub mod measurements;
pub mod particles;
pub mod run;
