//! `edmd experiment front`.
