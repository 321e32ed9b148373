//! Measurements: observers that any run can attach (being written).
