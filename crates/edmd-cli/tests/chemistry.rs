//! `edmd experiment reaction` and `annihilation`.
