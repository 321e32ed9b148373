//! One module per subcommand.

pub mod bench;
pub mod experiment;
pub mod gen;
pub mod measurements;
pub mod pack;
pub mod particles;
pub mod render;
pub mod run;
pub mod soak;
