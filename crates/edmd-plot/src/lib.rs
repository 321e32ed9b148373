//! Plots for edmd (being written).
