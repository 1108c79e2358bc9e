//! Typed parameter errors of the strain-energy constructors.

use thiserror::Error;

/// A strain-energy parameter outside its admissible range.
///
/// The message names the parameter, its value and the valid range:
///
/// ```
/// use celltissue::NeoHookean;
/// let err = NeoHookean::new(-1.0).unwrap_err();
/// assert_eq!(err.to_string(), "mu = -1 must be finite and > 0");
/// ```
#[derive(Clone, Debug, Error, PartialEq)]
#[non_exhaustive]
pub enum EnergyError {
    /// A scalar parameter is outside its valid range.
    #[error("{param} = {value} must be {range}")]
    OutOfRange {
        /// Parameter name as in the scenario file (e.g. `"mu"`, `"terms[1].mu_p*alpha_p"`).
        param: String,
        /// The offending value.
        value: f64,
        /// The valid range, e.g. `"finite and > 0"`.
        range: &'static str,
    },
    /// An Ogden law was given no terms.
    #[error("terms must contain at least one (mu_p, alpha_p) pair")]
    EmptyOgden,
    /// A state outside the law's domain (e.g. a locking law past its limit).
    #[error("{law}: {reason}")]
    OutsideDomain {
        /// The law's scenario name, e.g. `"gent"`.
        law: &'static str,
        /// The violated bound, with the stretches.
        reason: String,
    },
    /// A law's parameters do not deserialize (unknown or missing field, wrong type, or a
    /// range check of its constructor).
    #[error("{message}")]
    Params {
        /// The law's name.
        law: String,
        /// The deserializer's message (names the field).
        message: String,
    },
    /// No law of this name is registered ([`crate::energy::registry`]).
    #[error("unknown variant `{name}`; valid laws: {valid}")]
    UnknownLaw {
        /// The name asked for.
        name: String,
        /// The registered names, comma-separated.
        valid: String,
    },
    /// A registration was refused: the name is taken.
    #[error("a strain energy named `{0}` is already registered")]
    DuplicateLaw(String),
    /// A registration was refused: the name is not `[a-z0-9_]+`.
    #[error("a law name must be non-empty and hold only a-z, 0-9 and `_`; got `{0}`")]
    BadLawName(String),
    /// A formula law (`law = "expression"`) was rejected.
    #[error(transparent)]
    Expression(#[from] super::expression::ExpressionError),
}

impl EnergyError {
    /// Builds an [`EnergyError::OutOfRange`].
    ///
    /// ```
    /// use celltissue::EnergyError;
    /// let e = EnergyError::out_of_range("k1", -0.5, ">= 0");
    /// assert_eq!(e.to_string(), "k1 = -0.5 must be >= 0");
    /// ```
    pub fn out_of_range(param: impl Into<String>, value: f64, range: &'static str) -> Self {
        Self::OutOfRange {
            param: param.into(),
            value,
            range,
        }
    }
}

/// `Ok(v)` if `v` is finite and `> 0`, else an error naming `param`.
pub(crate) fn positive(param: &str, v: f64) -> Result<f64, EnergyError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(EnergyError::out_of_range(param, v, "finite and > 0"))
    }
}

/// `Ok(v)` if `v` is finite and `>= 0`, else an error naming `param`.
pub(crate) fn non_negative(param: &str, v: f64) -> Result<f64, EnergyError> {
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err(EnergyError::out_of_range(param, v, "finite and >= 0"))
    }
}

/// `Ok(v)` if `v` is finite, else an error naming `param`.
pub(crate) fn finite(param: &str, v: f64) -> Result<f64, EnergyError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(EnergyError::out_of_range(param, v, "finite"))
    }
}
