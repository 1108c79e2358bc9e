//! A strain energy written as a formula in the scenario file and differentiated automatically
//! (`law = { law = "expression", W = "mu/2*(I1 - 3)", mu = 1.0 }`, docs/model.md §1.1).
//!
//! The formula is parsed once into a small expression tree (an arena of [`Node`]s with constant
//! folding; parameters are folded in as constants) and evaluated generically over any
//! [`DualNum`], so the same tree serves `f64` and every nested dual the AD of [`super::ad`] uses.
//!
//! Grammar (usual precedence; `^` and `**` are right-associative powers; unary minus binds
//! looser than a power, so `-l1^2 = -(l1^2)`):
//!
//! ```text
//! expr    := expr ('+' | '-') expr | expr ('*' | '/') expr | expr ('^' | '**') expr
//!          | ('-' | '+') expr | '(' expr ')' | number | name | func '(' expr ')'
//! name    := l1 | l2 | l3 | I1 | I2 | pi | <parameter>
//! func    := exp | ln | log10 | sqrt | cbrt | sin | cos | tan | sinh | cosh | tanh | atan
//! ```
//!
//! `l1, l2, l3` are the principal stretches, `I1 = l1² + l2² + l3²` and
//! `I2 = l1²l2² + l2²l3² + l3²l1²` the invariants (the cells are incompressible, so `I3 = 1`).
//!
//! The parser is hand-written (a Pratt parser, ~150 lines): the expression crates available
//! (`exmex`, `evalexpr`, `meval`) evaluate in their own value type or need `FromStr` on the
//! scalar, so none evaluates one parsed tree over `f64` *and* the nested dual numbers without
//! re-parsing.
//!
//! ```
//! use celltissue::energy::Expression;
//! use celltissue::StrainEnergy;
//! let law = Expression::new("mu/2*(I1 - 3)", [("mu", 2.0)])?;
//! assert!((law.shear_modulus() - 2.0).abs() < 1e-12);
//! assert!((law.line(1.5).sigma - 2.0 * (1.5f64.powi(2) - 1.5f64.powi(-2))).abs() < 1e-12);
//! let err = Expression::new("mu/2*(J1 - 3)", [("mu", 1.0)]).unwrap_err();
//! assert!(err.to_string().starts_with("W at position 7: unknown name `J1`"));
//! # Ok::<(), celltissue::energy::ExpressionError>(())
//! ```

use num_dual::DualNum;
use serde::ser::SerializeMap;
use serde::{Serialize, Serializer};
use std::collections::BTreeMap;
use std::fmt;
use thiserror::Error;

/// The variables a formula may use, in the order of [`Node::Var`] indices.
pub const VARIABLES: [&str; 5] = ["l1", "l2", "l3", "I1", "I2"];

/// Functions a formula may call.
pub const FUNCTIONS: [&str; 12] = [
    "exp", "ln", "log10", "sqrt", "cbrt", "sin", "cos", "tan", "sinh", "cosh", "tanh", "atan",
];

/// A formula or parameter the expression law rejects. The message names the key (`W` or the
/// parameter) and, for the formula, the 1-based character position.
///
/// ```
/// use celltissue::energy::Expression;
/// let err = Expression::new("mu*(I1 - 3", [("mu", 1.0)]).unwrap_err();
/// assert_eq!(err.to_string(), "W at position 11 (end of formula): expected `)`");
/// ```
#[derive(Clone, Debug, Error, PartialEq)]
#[non_exhaustive]
pub enum ExpressionError {
    /// The formula does not parse or names something unknown.
    #[error("W at position {position}{}: {message}", context(.found))]
    Syntax {
        /// What is wrong.
        message: String,
        /// 1-based character position in the formula.
        position: usize,
        /// The token found there (`None` at the end of the formula).
        found: Option<String>,
    },
    /// A parameter is not a finite number, shadows a variable or function, or is never used.
    #[error("{key}: {message}")]
    Parameter {
        /// The parameter's key.
        key: String,
        /// What is wrong.
        message: String,
    },
    /// The formula parses but its small-strain behaviour is not a valid cell law.
    #[error("W: {0}")]
    Law(String),
}

fn context(found: &Option<String>) -> String {
    match found {
        None => " (end of formula)".into(),
        Some(_) => String::new(),
    }
}

/// A unary function of the formula language.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Func {
    /// `exp`
    Exp,
    /// `ln` (natural logarithm)
    Ln,
    /// `log10`
    Log10,
    /// `sqrt`
    Sqrt,
    /// `cbrt`
    Cbrt,
    /// `sin`
    Sin,
    /// `cos`
    Cos,
    /// `tan`
    Tan,
    /// `sinh`
    Sinh,
    /// `cosh`
    Cosh,
    /// `tanh`
    Tanh,
    /// `atan`
    Atan,
}

impl Func {
    fn from_name(s: &str) -> Option<Self> {
        Some(match s {
            "exp" => Self::Exp,
            "ln" => Self::Ln,
            "log10" => Self::Log10,
            "sqrt" => Self::Sqrt,
            "cbrt" => Self::Cbrt,
            "sin" => Self::Sin,
            "cos" => Self::Cos,
            "tan" => Self::Tan,
            "sinh" => Self::Sinh,
            "cosh" => Self::Cosh,
            "tanh" => Self::Tanh,
            "atan" => Self::Atan,
            _ => return None,
        })
    }

    #[inline]
    fn apply<D: DualNum<Primitive = f64> + Copy>(self, x: D) -> D {
        match self {
            Self::Exp => x.exp(),
            Self::Ln => x.ln(),
            Self::Log10 => x.log10(),
            Self::Sqrt => x.sqrt(),
            Self::Cbrt => x.cbrt(),
            Self::Sin => x.sin(),
            Self::Cos => x.cos(),
            Self::Tan => x.tan(),
            Self::Sinh => x.sinh(),
            Self::Cosh => x.cosh(),
            Self::Tanh => x.tanh(),
            Self::Atan => x.atan(),
        }
    }
}

/// One node of the parsed formula; children are indices into the arena, always smaller than
/// the node's own index (so the root is the last node).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Node {
    /// A number (literals, parameters and folded sub-expressions).
    Const(f64),
    /// A variable, an index into [`VARIABLES`].
    Var(u8),
    /// `-a`
    Neg(u32),
    /// `a + b`
    Add(u32, u32),
    /// `a - b`
    Sub(u32, u32),
    /// `a * b`
    Mul(u32, u32),
    /// `a / b`
    Div(u32, u32),
    /// `a ^ n` with a constant integer exponent.
    PowI(u32, i32),
    /// `a ^ c` with a constant real exponent.
    PowF(u32, f64),
    /// `a ^ b` with a variable exponent.
    Pow(u32, u32),
    /// `f(a)`
    Call(Func, u32),
}

/// A strain energy `W(l1, l2, l3)` given by a formula in the principal stretches and/or the
/// invariants `I1`, `I2`, with named parameters. Implements [`super::StrainEnergy`] by evaluating
/// the parsed tree over the AD scalar; the small-strain shear modulus is derived from the
/// formula (`μ = dσ_el/da(1)/4`, docs/model.md §1.2) and must be finite and positive.
///
/// Serializes back to its scenario form (`W` and the parameters).
///
/// ```
/// use celltissue::energy::Expression;
/// use celltissue::{MooneyRivlin, StrainEnergy};
/// // Mooney–Rivlin written in the invariants reproduces the built-in law (sheet: I1 ≠ I2).
/// let e = Expression::new("c1*(I1 - 3) + c2*(I2 - 3)", [("c1", 0.3), ("c2", 0.2)])?;
/// let m = MooneyRivlin::new(0.3, 0.2).unwrap();
/// let (a, b) = (e.sheet(0.9, 1.2), m.sheet(0.9, 1.2));
/// assert!((a.s11 - b.s11).abs() < 1e-12 && (a.tangent[0][1] - b.tangent[0][1]).abs() < 1e-12);
/// # Ok::<(), celltissue::energy::ExpressionError>(())
/// ```
#[derive(Clone, Debug)]
pub struct Expression {
    source: String,
    params: BTreeMap<String, f64>,
    nodes: Vec<Node>,
    /// Which of `I1`, `I2` the tree reads (computed only if needed).
    uses_invariants: [bool; 2],
    mu: f64,
}

impl PartialEq for Expression {
    fn eq(&self, other: &Self) -> bool {
        self.source == other.source && self.params == other.params
    }
}

impl Expression {
    /// Parses `formula` with the given named parameters. Errors name the key (`W` or the
    /// parameter) and, for the formula, the position: unknown names, bad syntax, parameters
    /// that are not finite, shadow a variable or function, or are unused, and formulas whose
    /// small-strain shear modulus is not finite and positive.
    ///
    /// ```
    /// use celltissue::energy::Expression;
    /// assert!(Expression::new("mu/2*(I1 - 3)", [("mu", 1.0), ("nu", 0.3)])
    ///     .unwrap_err()
    ///     .to_string()
    ///     .contains("nu: parameter is not used by W"));
    /// ```
    pub fn new<'a>(
        formula: &str,
        params: impl IntoIterator<Item = (&'a str, f64)>,
    ) -> Result<Self, ExpressionError> {
        let params: BTreeMap<String, f64> =
            params.into_iter().map(|(k, v)| (k.to_owned(), v)).collect();
        for (k, &v) in &params {
            let bad = |message: &str| ExpressionError::Parameter {
                key: k.clone(),
                message: message.into(),
            };
            if !v.is_finite() {
                return Err(bad(&format!("= {v} must be a finite number")));
            }
            if VARIABLES.contains(&k.as_str()) || FUNCTIONS.contains(&k.as_str()) || k == "pi" {
                return Err(bad(
                    "a parameter may not be named like a variable or function",
                ));
            }
            if !is_name(k) {
                return Err(bad(
                    "a parameter name must start with a letter or `_` and hold only letters, digits and `_`",
                ));
            }
        }
        let mut parser = Parser::new(formula, &params)?;
        parser.parse_root()?;
        if let Some(unused) = params.keys().find(|k| !parser.used.contains(*k)) {
            return Err(ExpressionError::Parameter {
                key: unused.clone(),
                message: "parameter is not used by W".into(),
            });
        }
        let uses_invariants = [
            parser.nodes.contains(&Node::Var(3)),
            parser.nodes.contains(&Node::Var(4)),
        ];
        let nodes = std::mem::take(&mut parser.nodes);
        drop(parser);
        let mut law = Self {
            source: formula.to_owned(),
            params,
            nodes,
            uses_invariants,
            mu: f64::NAN,
        };
        let dsigma = super::ad::line(&law, 1.0).dsigma;
        if !(dsigma.is_finite() && dsigma > 0.0) {
            return Err(ExpressionError::Law(format!(
                "small-strain modulus dσ_el/da(1) = {dsigma} must be finite and > 0 (W must stiffen under stretch at the reference state)"
            )));
        }
        law.mu = 0.25 * dsigma;
        Ok(law)
    }

    /// The formula as written.
    ///
    /// ```
    /// use celltissue::energy::Expression;
    /// let e = Expression::new("mu/2*(I1 - 3)", [("mu", 1.0)])?;
    /// assert_eq!(e.formula(), "mu/2*(I1 - 3)");
    /// # Ok::<(), celltissue::energy::ExpressionError>(())
    /// ```
    pub fn formula(&self) -> &str {
        &self.source
    }

    /// The parameters by name.
    ///
    /// ```
    /// use celltissue::energy::Expression;
    /// let e = Expression::new("c1*(I1 - 3) + c2*(I2 - 3)", [("c1", 0.3), ("c2", 0.2)])?;
    /// assert_eq!(e.params()["c2"], 0.2);
    /// # Ok::<(), celltissue::energy::ExpressionError>(())
    /// ```
    pub fn params(&self) -> &BTreeMap<String, f64> {
        &self.params
    }

    /// The parsed tree (root last).
    #[cfg(test)]
    pub(crate) fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    /// Evaluates `W` at the stretches `l`, generically over the scalar.
    ///
    /// ```
    /// use celltissue::energy::Expression;
    /// let e = Expression::new("k*(l1 - 1)^2 + I1", [("k", 2.0)])?;
    /// assert_eq!(e.eval([2.0, 1.0, 1.0]), 2.0 + 6.0);
    /// # Ok::<(), celltissue::energy::ExpressionError>(())
    /// ```
    #[inline]
    pub fn eval<D: DualNum<Primitive = f64> + Copy>(&self, l: [D; 3]) -> D {
        let zero = D::from(0.0);
        let sq = [l[0] * l[0], l[1] * l[1], l[2] * l[2]];
        let i1 = if self.uses_invariants[0] {
            sq[0] + sq[1] + sq[2]
        } else {
            zero
        };
        let i2 = if self.uses_invariants[1] {
            sq[0] * sq[1] + sq[1] * sq[2] + sq[2] * sq[0]
        } else {
            zero
        };
        let vars = [l[0], l[1], l[2], i1, i2];
        self.eval_node(self.nodes.len() - 1, &vars)
    }

    fn eval_node<D: DualNum<Primitive = f64> + Copy>(&self, i: usize, v: &[D; 5]) -> D {
        let e = |j: u32| self.eval_node(j as usize, v);
        match self.nodes[i] {
            Node::Const(c) => D::from(c),
            Node::Var(k) => v[k as usize],
            Node::Neg(a) => -e(a),
            Node::Add(a, b) => e(a) + e(b),
            Node::Sub(a, b) => e(a) - e(b),
            Node::Mul(a, b) => e(a) * e(b),
            Node::Div(a, b) => e(a) / e(b),
            Node::PowI(a, n) => e(a).powi(n),
            Node::PowF(a, c) => e(a).powf(c),
            Node::Pow(a, b) => e(a).powd(e(b)),
            Node::Call(f, a) => f.apply(e(a)),
        }
    }
}

impl super::StrainEnergy for Expression {
    #[inline]
    fn energy<D: DualNum<Primitive = f64> + Copy>(&self, l: [D; 3]) -> D {
        self.eval(l)
    }

    fn shear_modulus(&self) -> f64 {
        self.mu
    }
}

impl Serialize for Expression {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(Some(1 + self.params.len()))?;
        m.serialize_entry("W", &self.source)?;
        for (k, v) in &self.params {
            m.serialize_entry(k, v)?;
        }
        m.end()
    }
}

impl fmt::Display for Expression {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "W = {}", self.source)?;
        for (k, v) in &self.params {
            write!(f, ", {k} = {v}")?;
        }
        Ok(())
    }
}

fn is_name(s: &str) -> bool {
    let mut c = s.chars();
    c.next()
        .is_some_and(|c0| c0.is_ascii_alphabetic() || c0 == '_')
        && c.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Num(f64),
    Name(String),
    Op(char),
    Pow,
    LParen,
    RParen,
}

impl fmt::Display for Tok {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Tok::Num(x) => write!(f, "{x}"),
            Tok::Name(s) => write!(f, "{s}"),
            Tok::Op(c) => write!(f, "{c}"),
            Tok::Pow => write!(f, "^"),
            Tok::LParen => write!(f, "("),
            Tok::RParen => write!(f, ")"),
        }
    }
}

/// Splits the formula into tokens with their 1-based character positions.
fn lex(src: &str) -> Result<Vec<(Tok, usize)>, ExpressionError> {
    let chars: Vec<char> = src.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let pos = i + 1;
        if c.is_whitespace() {
            i += 1;
        } else if c.is_ascii_digit() || c == '.' {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
                i += 1;
            }
            if i < chars.len() && (chars[i] == 'e' || chars[i] == 'E') {
                let mut j = i + 1;
                if j < chars.len() && (chars[j] == '+' || chars[j] == '-') {
                    j += 1;
                }
                if j < chars.len() && chars[j].is_ascii_digit() {
                    i = j;
                    while i < chars.len() && chars[i].is_ascii_digit() {
                        i += 1;
                    }
                }
            }
            let text: String = chars[start..i].iter().collect();
            let x = text.parse::<f64>().map_err(|_| ExpressionError::Syntax {
                message: format!("malformed number `{text}`"),
                position: pos,
                found: Some(text.clone()),
            })?;
            out.push((Tok::Num(x), pos));
        } else if c.is_ascii_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            out.push((Tok::Name(chars[start..i].iter().collect()), pos));
        } else {
            i += 1;
            let tok = match c {
                '*' if chars.get(i) == Some(&'*') => {
                    i += 1;
                    Tok::Pow
                }
                '^' => Tok::Pow,
                '+' | '-' | '*' | '/' => Tok::Op(c),
                '(' => Tok::LParen,
                ')' => Tok::RParen,
                _ => {
                    return Err(ExpressionError::Syntax {
                        message: format!("unexpected character `{c}`"),
                        position: pos,
                        found: Some(c.to_string()),
                    })
                }
            };
            out.push((tok, pos));
        }
    }
    Ok(out)
}

/// Pratt parser building the node arena with constant folding.
struct Parser<'p> {
    toks: Vec<(Tok, usize)>,
    at: usize,
    end: usize,
    params: &'p BTreeMap<String, f64>,
    used: Vec<String>,
    nodes: Vec<Node>,
}

const BP_ADD: u8 = 10;
const BP_MUL: u8 = 20;
const BP_NEG: u8 = 25;
const BP_POW: u8 = 30;

impl<'p> Parser<'p> {
    fn new(src: &str, params: &'p BTreeMap<String, f64>) -> Result<Self, ExpressionError> {
        Ok(Self {
            toks: lex(src)?,
            at: 0,
            end: src.chars().count() + 1,
            params,
            used: Vec::new(),
            nodes: Vec::new(),
        })
    }

    fn err(&self, message: String) -> ExpressionError {
        let (position, found) = match self.toks.get(self.at) {
            Some((t, p)) => (*p, Some(t.to_string())),
            None => (self.end, None),
        };
        ExpressionError::Syntax {
            message,
            position,
            found,
        }
    }

    fn peek(&self) -> Option<&Tok> {
        self.toks.get(self.at).map(|t| &t.0)
    }

    fn parse_root(&mut self) -> Result<(), ExpressionError> {
        if self.toks.is_empty() {
            return Err(self.err("empty formula".into()));
        }
        let root = self.expr(0)?;
        if let Some(t) = self.peek() {
            return Err(self.err(format!("unexpected `{t}` after a complete expression")));
        }
        // The root must be the last node: re-push it if folding left it elsewhere.
        if root as usize != self.nodes.len() - 1 {
            let n = self.nodes[root as usize];
            self.nodes.push(n);
        }
        Ok(())
    }

    fn push(&mut self, n: Node) -> u32 {
        self.nodes.push(n);
        (self.nodes.len() - 1) as u32
    }

    fn constant(&self, i: u32) -> Option<f64> {
        match self.nodes[i as usize] {
            Node::Const(c) => Some(c),
            _ => None,
        }
    }

    /// A binary node, folded when both sides are constants.
    fn binary(&mut self, op: char, a: u32, b: u32) -> u32 {
        if let (Some(x), Some(y)) = (self.constant(a), self.constant(b)) {
            let v = match op {
                '+' => x + y,
                '-' => x - y,
                '*' => x * y,
                '/' => x / y,
                _ => x.powf(y),
            };
            return self.push(Node::Const(v));
        }
        let node = match op {
            '+' => Node::Add(a, b),
            '-' => Node::Sub(a, b),
            '*' => Node::Mul(a, b),
            '/' => Node::Div(a, b),
            _ => match self.constant(b) {
                Some(c) if c.fract() == 0.0 && c.abs() <= 64.0 => Node::PowI(a, c as i32),
                Some(c) => Node::PowF(a, c),
                None => Node::Pow(a, b),
            },
        };
        self.push(node)
    }

    fn expr(&mut self, min_bp: u8) -> Result<u32, ExpressionError> {
        let mut lhs = self.prefix()?;
        loop {
            let (op, bp, right_bp) = match self.peek() {
                Some(Tok::Op(c @ ('+' | '-'))) => (*c, BP_ADD, BP_ADD + 1),
                Some(Tok::Op(c @ ('*' | '/'))) => (*c, BP_MUL, BP_MUL + 1),
                Some(Tok::Pow) => ('^', BP_POW, BP_POW), // right-associative
                Some(Tok::RParen) | None => break,
                Some(t) => {
                    return Err(self.err(format!("expected an operator or `)`, found `{t}`")))
                }
            };
            if bp < min_bp {
                break;
            }
            self.at += 1;
            let rhs = self.expr(right_bp)?;
            lhs = self.binary(op, lhs, rhs);
        }
        Ok(lhs)
    }

    fn prefix(&mut self) -> Result<u32, ExpressionError> {
        let Some((tok, _)) = self.toks.get(self.at).cloned() else {
            return Err(self.err("expected a number, name or `(`".into()));
        };
        self.at += 1;
        match tok {
            Tok::Num(x) => Ok(self.push(Node::Const(x))),
            Tok::Op('-') => {
                let a = self.expr(BP_NEG)?;
                Ok(match self.constant(a) {
                    Some(c) => self.push(Node::Const(-c)),
                    None => self.push(Node::Neg(a)),
                })
            }
            Tok::Op('+') => self.expr(BP_NEG),
            Tok::LParen => {
                let a = self.expr(0)?;
                self.expect_rparen()?;
                Ok(a)
            }
            Tok::Name(name) => self.name(&name),
            other => {
                self.at -= 1;
                Err(self.err(format!("expected a number, name or `(`, found `{other}`")))
            }
        }
    }

    fn expect_rparen(&mut self) -> Result<(), ExpressionError> {
        if self.peek() == Some(&Tok::RParen) {
            self.at += 1;
            Ok(())
        } else {
            Err(self.err("expected `)`".into()))
        }
    }

    fn name(&mut self, name: &str) -> Result<u32, ExpressionError> {
        if let Some(k) = VARIABLES.iter().position(|v| *v == name) {
            return Ok(self.push(Node::Var(k as u8)));
        }
        if let Some(&v) = self.params.get(name) {
            if !self.used.iter().any(|u| u == name) {
                self.used.push(name.to_owned());
            }
            return Ok(self.push(Node::Const(v)));
        }
        if name == "pi" {
            return Ok(self.push(Node::Const(std::f64::consts::PI)));
        }
        if let Some(f) = Func::from_name(name) {
            if self.peek() != Some(&Tok::LParen) {
                return Err(self.err(format!("expected `(` after function `{name}`")));
            }
            self.at += 1;
            let a = self.expr(0)?;
            self.expect_rparen()?;
            return Ok(match self.constant(a) {
                Some(c) => self.push(Node::Const(f.apply(c))),
                None => self.push(Node::Call(f, a)),
            });
        }
        self.at -= 1;
        let mut valid: Vec<&str> = VARIABLES.to_vec();
        valid.extend(self.params.keys().map(String::as_str));
        valid.push("pi");
        Err(self.err(format!(
            "unknown name `{name}`; valid names: {}; functions: {}",
            valid.join(", "),
            FUNCTIONS.join(", ")
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::{ad, Hgo, NeoHookean, Ogden, StrainEnergy};

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs().max(1e-300)
    }

    #[test]
    fn precedence_and_associativity() {
        let e = |s: &str| Expression::new(s, []).unwrap().eval([2.0, 1.0, 1.0]);
        // l1 = 2 so the formulas stay valid cell laws (positive modulus) where needed.
        assert_eq!(e("l1 + 2*l1^2"), 2.0 + 8.0);
        assert_eq!(e("2^3^l1 + l1*0"), 2f64.powf(9.0)); // right-associative
        assert_eq!(e("-l1^2 + 2*l1^2"), 4.0); // -(l1²) + 2l1²
        assert_eq!(e("l1**2 - (l1 - 1)/2"), 4.0 - 0.5);
        assert_eq!(e("1.5e1*l1^2 + 2E-1*l1^2"), 15.2 * 4.0);
        assert_eq!(e("exp(l1) + pi*0 + l1^2"), 2f64.exp() + 4.0);
    }

    #[test]
    fn constants_fold_and_parameters_are_constants() {
        let e = Expression::new("mu/2*(l1^2 + l2^2 + l3^2 - 3)", [("mu", 2.0)]).unwrap();
        // mu/2 folds to one constant; the root is the last node.
        assert!(e.nodes().contains(&Node::Const(1.0)));
        assert!(matches!(e.nodes().last(), Some(Node::Mul(..))));
        assert!(e.nodes().iter().any(|n| matches!(n, Node::PowI(_, 2))));
    }

    /// The expression law reproduces the built-in laws' responses (line, sheet, shear) to
    /// round-off, through the nested-dual AD.
    #[test]
    fn matches_built_in_laws() {
        let cases: Vec<(Expression, crate::AnyEnergy)> = vec![
            (
                Expression::new("mu/2*(I1 - 3)", [("mu", 1.3)]).unwrap(),
                NeoHookean::new(1.3).unwrap().into(),
            ),
            (
                Expression::new(
                    "m1/a1*(l1^a1 + l2^a1 + l3^a1 - 3) + m2/a2*(l1^a2 + l2^a2 + l3^a2 - 3)",
                    [("m1", 0.8), ("a1", 3.0), ("m2", -0.05), ("a2", -2.0)],
                )
                .unwrap(),
                Ogden::new(vec![(0.8, 3.0), (-0.05, -2.0)]).unwrap().into(),
            ),
        ];
        for (e, b) in &cases {
            assert!(rel(e.shear_modulus(), b.shear_modulus()) < 1e-13);
            for a in [0.3, 0.9, 1.0, 1.7] {
                let (x, y) = (e.line(a), b.line(a));
                assert!(rel(x.sigma, y.sigma) < 1e-12 || (x.sigma - y.sigma).abs() < 1e-14);
                assert!(rel(x.dsigma, y.dsigma) < 1e-12);
                assert!(rel(x.pressure, y.pressure) < 1e-12);
                let (s, t) = (e.sheet(a, 1.1), b.sheet(a, 1.1));
                assert!(rel(s.s22, t.s22) < 1e-12 && rel(s.tangent[1][0], t.tangent[1][0]) < 1e-12);
                let (s, t) = (e.shear(a), b.shear(a));
                assert!(rel(s.tau, t.tau) < 1e-12 && rel(s.dtau, t.dtau) < 1e-12);
            }
        }
        // HGO's fibre term through the formula language on its tensile side.
        let th: f64 = 0.4;
        let hgo = Hgo::new(0.9, 0.7, 1.5, th).unwrap();
        let e = Expression::new(
            "c/2*(I1 - 3) + k1/(2*k2)*(exp(k2*(l1^2*cs + l2^2*sn - 1)^2) - 1)",
            [
                ("c", 0.9),
                ("k1", 0.7),
                ("k2", 1.5),
                ("cs", th.cos().powi(2)),
                ("sn", th.sin().powi(2)),
            ],
        )
        .unwrap();
        let (x, y) = (ad::line(&e, 1.3), hgo.line(1.3));
        assert!(rel(x.sigma, y.sigma) < 1e-12 && rel(x.dsigma, y.dsigma) < 1e-12);
    }

    #[test]
    fn errors_name_key_and_position() {
        let msg = |s: &str, p: &[(&str, f64)]| {
            Expression::new(s, p.iter().copied())
                .unwrap_err()
                .to_string()
        };
        assert_eq!(
            msg("mu*(I1 - 3) +", &[("mu", 1.0)]),
            "W at position 14 (end of formula): expected a number, name or `(`"
        );
        assert!(msg("mu*(I1 - 3))", &[("mu", 1.0)])
            .starts_with("W at position 12: unexpected `)` after a complete expression"));
        assert!(msg("mu*(I1 # 3)", &[("mu", 1.0)])
            .starts_with("W at position 8: unexpected character `#`"));
        assert!(msg("mu*(I3 - 3)", &[("mu", 1.0)]).starts_with(
            "W at position 5: unknown name `I3`; valid names: l1, l2, l3, I1, I2, mu, pi"
        ));
        assert!(msg("mu*exp 2", &[("mu", 1.0)]).contains("expected `(` after function `exp`"));
        assert!(msg("mu (I1 - 3)", &[("mu", 1.0)])
            .starts_with("W at position 4: expected an operator or `)`, found `(`"));
        assert_eq!(
            msg("", &[]),
            "W at position 1 (end of formula): empty formula"
        );
        assert_eq!(
            msg("mu*(I1 - 3)", &[("mu", f64::NAN)]),
            "mu: = NaN must be a finite number"
        );
        assert!(msg("l1*(I1 - 3)", &[("l1", 1.0)]).starts_with("l1: a parameter may not"));
        // No stiffness at the reference state: rejected, not run.
        assert!(msg("mu*(I1 - 3)^2", &[("mu", 1.0)]).contains("small-strain modulus"));
        assert!(msg("-mu*(I1 - 3)", &[("mu", 1.0)]).contains("must be finite and > 0"));
    }
}
