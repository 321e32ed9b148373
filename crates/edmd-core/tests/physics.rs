//! Physics checked against physics: kinetic theory and the hard-disc equation of state.
