//! The values options take, shared by every front door: the names of formats, column orders,
//! collision rules and boundaries (clap's `ValueEnum`, so the command line and Python spell
//! them alike), and the parsers of numbers with their ranges.

use clap::ValueEnum;

/// Input file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum FormatArg {
    /// Detect from the second line (one number: course; nine: Princeton).
    Auto,
    /// The "Collisions" course format: N, R, Lx Ly, then x y u v per disc.
    Course,
    /// The Princeton format: N, then rx ry vx vy radius mass r g b per disc.
    Princeton,
}

/// Column order of the Princeton format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ColumnsArg {
    /// `radius mass`, as in the published data files.
    RadiusMass,
    /// `mass radius`, as in the assignment's prose.
    MassRadius,
}

/// Collision rule.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum RuleArg {
    /// Impulse along the line of centres (any masses).
    Elastic,
    /// The two discs exchange velocities (course rule; equal masses).
    Swap,
}

/// Heat bath.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ThermostatArg {
    /// Andersen: velocities redrawn from Maxwell-Boltzmann at Poisson times.
    Andersen,
}

/// Boundary kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum BoundaryArg {
    /// Periodic in both directions.
    Periodic,
    /// Reflecting walls.
    Walls,
}

/// A dimension for the commands that take rods on a line too (`edmd gen`, `edmd experiment
/// eos`, `edmd bench`): 1, 2 or 3.
pub fn parse_dim_with_rods(s: &str) -> Result<usize, String> {
    match s.trim() {
        "1" => Ok(1),
        _ => parse_dim(s).map_err(|_| format!("the dimension must be 1, 2 or 3, found '{s}'")),
    }
}

/// A dimension: 2 or 3. The commands that do not take rods refuse 1 here, by name.
pub fn parse_dim(s: &str) -> Result<usize, String> {
    if s.trim() == "1" {
        return Err(
            "this command takes 2 or 3 dimensions; rods on a line (--dim 1) are for gen, run, render, bench, soak and experiment eos"
                .into(),
        );
    }
    match s.trim() {
        "2" => Ok(2),
        "3" => Ok(3),
        _ => Err(format!("the dimension must be 2 or 3, found '{s}'")),
    }
}

fn parse_number(s: &str) -> Result<f64, String> {
    let x: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not a number"))?;
    if !x.is_finite() {
        return Err(format!("'{s}' is not a finite number"));
    }
    Ok(x)
}

/// A time `>= 0`.
pub fn parse_time(s: &str) -> Result<f64, String> {
    let x = parse_number(s)?;
    if x < 0.0 {
        return Err(format!("the end time must be >= 0, found {s}"));
    }
    Ok(x)
}

/// A number `> 0`.
pub fn parse_positive(s: &str) -> Result<f64, String> {
    let x = parse_number(s)?;
    if x <= 0.0 {
        return Err(format!("must be > 0, found {s}"));
    }
    Ok(x)
}

/// A number `>= 0`.
pub fn parse_non_negative(s: &str) -> Result<f64, String> {
    let x = parse_number(s)?;
    if x < 0.0 {
        return Err(format!("must be >= 0, found {s}"));
    }
    Ok(x)
}

/// A count `>= 1`.
pub fn parse_count(s: &str) -> Result<usize, String> {
    match s.trim().parse::<usize>() {
        Ok(n) if n >= 1 => Ok(n),
        _ => Err(format!("must be a whole number >= 1, found '{s}'")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_flags() {
        assert_eq!(parse_time("20"), Ok(20.0));
        assert_eq!(parse_time("0"), Ok(0.0));
        assert!(parse_time("-1").unwrap_err().contains(">= 0"));
        assert!(parse_time("nan").unwrap_err().contains("finite"));
        assert!(parse_time("inf").unwrap_err().contains("finite"));
        assert!(parse_time("abc").unwrap_err().contains("not a number"));
        assert!(parse_positive("0").is_err());
        assert!(parse_count("0").is_err());
        assert!(parse_count("-5").is_err());
        assert_eq!(parse_count("10000"), Ok(10000));
    }
}
