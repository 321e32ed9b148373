//! One module per subcommand.

pub mod bench;
pub mod particles;
pub mod run;
