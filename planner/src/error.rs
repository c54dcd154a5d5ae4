//! Errors the planner reports. Input errors carry a JSON pointer into the request.

use std::fmt;

/// A problem with the caller's input: what is wrong and where (a JSON pointer such as
/// `/area/coordinates/0/3`).
#[derive(Debug, Clone, PartialEq)]
pub struct InputError {
    pub code: &'static str,
    pub pointer: String,
    pub detail: String,
}

impl InputError {
    pub fn new(code: &'static str, pointer: impl Into<String>, detail: impl Into<String>) -> Self {
        Self { code, pointer: pointer.into(), detail: detail.into() }
    }
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} (at {})", self.detail, self.pointer)
    }
}

/// Checks that `value` is finite and within `[lo, hi]`.
pub fn check_range(value: f64, lo: f64, hi: f64, pointer: &str, unit: &str) -> Result<(), InputError> {
    if !value.is_finite() || value < lo || value > hi {
        return Err(InputError::new("parameter_out_of_range", pointer, format!("{value} is outside the accepted range [{lo}, {hi}] {unit}")));
    }
    Ok(())
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlanError {
    #[error("{0}")]
    Input(InputError),
    /// The geometry is valid but no flyable plan exists (for example a part of the field that
    /// no path outside the no-fly zones can reach).
    #[error("{0}")]
    Infeasible(String),
    #[error("cancelled")]
    Cancelled,
}

impl From<InputError> for PlanError {
    fn from(e: InputError) -> Self {
        PlanError::Input(e)
    }
}
