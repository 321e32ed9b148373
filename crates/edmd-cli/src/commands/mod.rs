//! One module per subcommand.

pub mod bench;
pub mod experiment;
pub mod pack;
pub mod particles;
pub mod render;
pub mod run;
pub mod soak;
