//! RS274NGC expressions as LinuxCNC reads them: numbers, parameters (`#5`, `##1`, `#[1+2]`,
//! `#<name>`), bracketed expressions `[ ]` with binary operators, unary functions and unary
//! signs in front of any value.
//!
//! Precedence, lowest first (operators of one level are applied left to right, so
//! `2**3**2` is 64 and `[1 + 2 * 3 GT 6 AND 1]` is 1):
//!
//! | level | operators |
//! |---|---|
//! | 1 | `AND` `OR` `XOR` (0 is false, anything else true; the result is 0 or 1) |
//! | 2 | `EQ` `NE` `GT` `GE` `LT` `LE` (`EQ`/`NE` compare within 0.0001) |
//! | 3 | `+` `-` |
//! | 4 | `*` `/` `MOD` (`MOD` is never negative: `-7 MOD 3` is 2) |
//! | 5 | `**` |
//!
//! Functions (angles in degrees): `ABS ACOS ASIN COS EXP FIX FUP LN ROUND SIN SQRT TAN`,
//! `ATAN[y]/[x]` (two arguments, −180..180°) and `EXISTS[#<name>]`. `FIX` rounds down, `FUP`
//! up, `ROUND` half away from zero. Names and operators are case-insensitive; blanks are
//! ignored everywhere (LinuxCNC removes them before reading), so `#<tool dia>` is
//! `#<tooldia>`. A result that is not finite (division by zero, `SQRT[-1]`, `LN[0]`, `ACOS[2]`,
//! a negative number to a fractional power) is an error.

/// Values nested deeper than this (brackets, functions, signs, `#` of `#`) are refused, so a
/// hostile line cannot exhaust the stack.
const MAX_DEPTH: usize = 64;
/// `EQ` and `NE` compare within this (LinuxCNC's `TOLERANCE_EQUAL`).
const TOLERANCE_EQUAL: f64 = 0.0001;
/// Largest magnitude a number may have (1e12 mm is far beyond any machine; the bound keeps
/// every later computation finite).
pub(super) const MAX_MAGNITUDE: f64 = 1e12;
/// Numbered parameters `#1` .. `#5601` (LinuxCNC's `RS274NGC_MAX_PARAMETERS` is 5602).
pub(super) const PARAMETER_LIMIT: usize = 5602;

/// A unary function.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Func {
    Abs,
    Acos,
    Asin,
    Cos,
    Exp,
    Fix,
    Fup,
    Ln,
    Round,
    Sin,
    Sqrt,
    Tan,
}

/// A binary operator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Op {
    And,
    Or,
    Xor,
    Eq,
    Ne,
    Gt,
    Ge,
    Lt,
    Le,
    Plus,
    Minus,
    Times,
    Divide,
    Modulo,
    Power,
}

impl Op {
    fn precedence(self) -> u8 {
        match self {
            Self::And | Self::Or | Self::Xor => 1,
            Self::Eq | Self::Ne | Self::Gt | Self::Ge | Self::Lt | Self::Le => 2,
            Self::Plus | Self::Minus => 3,
            Self::Times | Self::Divide | Self::Modulo => 4,
            Self::Power => 5,
        }
    }
}

/// A parsed value.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Expr {
    Number(f64),
    /// `#expr`: a numbered parameter.
    Numbered(Box<Expr>),
    /// `#<name>` (lower case, without blanks).
    Named(String),
    /// `EXISTS[#<name>]` or `EXISTS[#n]`.
    Exists(Box<ParamName>),
    Neg(Box<Expr>),
    Func(Func, Box<Expr>),
    /// `ATAN[y]/[x]`.
    Atan(Box<Expr>, Box<Expr>),
    Binary(Op, Box<Expr>, Box<Expr>),
}

/// The parameter an assignment or `EXISTS` names.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum ParamName {
    Numbered(Expr),
    Named(String),
}

/// What expressions read: parameter values.
pub(super) trait ParamSource {
    /// The value of numbered parameter `index` (1 ..= 5601); an error message where reading
    /// it is refused.
    ///
    /// # Errors
    /// A message naming why the parameter cannot be read.
    fn numbered(&self, index: usize) -> Result<f64, String>;
    /// The value of a named parameter, `None` where it is not defined.
    fn named(&self, name: &str) -> Option<f64>;
}

/// A source without parameters: every numbered one reads 0, no named one exists.
pub(super) struct NoParams;

impl ParamSource for NoParams {
    fn numbered(&self, _index: usize) -> Result<f64, String> {
        Ok(0.0)
    }
    fn named(&self, _name: &str) -> Option<f64> {
        None
    }
}

/// A parse error: 0-based character index and message.
pub(super) type ParseError = (usize, String);

/// Reads values from a line's characters.
pub(super) struct Reader<'a> {
    chars: &'a [char],
    /// Index of the next character.
    pub(super) at: usize,
    depth: usize,
}

impl<'a> Reader<'a> {
    pub(super) fn new(chars: &'a [char], at: usize) -> Self {
        Self {
            chars,
            at,
            depth: 0,
        }
    }

    fn skip_blanks(&mut self) {
        while self.chars.get(self.at).is_some_and(|c| c.is_whitespace()) {
            self.at += 1;
        }
    }

    /// The next non-blank character (not consumed).
    pub(super) fn peek(&mut self) -> Option<char> {
        self.skip_blanks();
        self.chars.get(self.at).copied()
    }

    /// The next non-blank characters, lower case, up to `n` of them (blanks skipped).
    fn peek_word(&self, n: usize) -> String {
        let mut out = String::new();
        let mut i = self.at;
        while out.len() < n {
            match self.chars.get(i) {
                Some(c) if c.is_whitespace() => {}
                Some(c) => out.push(c.to_ascii_lowercase()),
                None => break,
            }
            i += 1;
        }
        out
    }

    /// Consume `n` non-blank characters.
    fn take(&mut self, n: usize) {
        let mut taken = 0;
        while taken < n {
            match self.chars.get(self.at) {
                Some(c) if c.is_whitespace() => {}
                Some(_) => taken += 1,
                None => return,
            }
            self.at += 1;
        }
    }

    fn err(&self, message: impl Into<String>) -> ParseError {
        (self.at, message.into())
    }

    /// The name of a function starting here, with its length, if one does and a `[` follows.
    pub(super) fn function_ahead(&self) -> Option<(&'static str, usize)> {
        const NAMES: [&str; 15] = [
            "exists", "abs", "acos", "asin", "atan", "cos", "exp", "fix", "fup", "ln", "round",
            "sin", "sqrt", "tan", "",
        ];
        let ahead = self.peek_word(7);
        NAMES
            .iter()
            .filter(|n| !n.is_empty())
            .find(|n| {
                ahead.starts_with(**n) && ahead.get(n.len()..n.len() + 1).is_some_and(|c| c == "[")
            })
            .map(|n| (*n, n.len()))
    }

    /// A real value: a number, a parameter, a bracketed expression, a function, or any of
    /// these after a `+` or `-`.
    ///
    /// # Errors
    /// Where the characters do not form a value.
    pub(super) fn value(&mut self) -> Result<Expr, ParseError> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(self.err(format!("expression nested deeper than {MAX_DEPTH} levels")));
        }
        let v = self.value_inner();
        self.depth -= 1;
        v
    }

    fn value_inner(&mut self) -> Result<Expr, ParseError> {
        match self.peek() {
            None => Err(self.err("a value is missing at the end of the line")),
            Some('[') => {
                self.take(1);
                self.expression()
            }
            Some('#') => {
                self.take(1);
                Ok(match self.param_name()? {
                    ParamName::Numbered(e) => Expr::Numbered(Box::new(e)),
                    ParamName::Named(n) => Expr::Named(n),
                })
            }
            Some(s @ ('+' | '-')) if !self.digit_after_sign() => {
                self.take(1);
                let v = self.value()?;
                Ok(if s == '-' { Expr::Neg(Box::new(v)) } else { v })
            }
            Some(c) if c.is_ascii_alphabetic() => self.function(),
            Some(_) => self.number().map(Expr::Number),
        }
    }

    fn digit_after_sign(&self) -> bool {
        let ahead = self.peek_word(2);
        ahead
            .chars()
            .nth(1)
            .is_some_and(|c| c.is_ascii_digit() || c == '.')
    }

    /// After `#`: `<name>` or an integer-valued value.
    pub(super) fn param_name(&mut self) -> Result<ParamName, ParseError> {
        if self.peek() == Some('<') {
            self.take(1);
            let mut name = String::new();
            loop {
                match self.chars.get(self.at) {
                    Some('>') => {
                        self.at += 1;
                        break;
                    }
                    Some(c) if c.is_whitespace() => {}
                    Some(c) if c.is_ascii_graphic() && *c != '<' => {
                        name.push(c.to_ascii_lowercase());
                    }
                    Some(c) => {
                        return Err(self.err(format!("character {c:?} in a parameter name")));
                    }
                    None => return Err(self.err("parameter name '<' is not closed by '>'")),
                }
                self.at += 1;
            }
            if name.is_empty() {
                return Err(self.err("empty parameter name #<>"));
            }
            Ok(ParamName::Named(name))
        } else {
            Ok(ParamName::Numbered(self.value()?))
        }
    }

    fn function(&mut self) -> Result<Expr, ParseError> {
        let Some((name, len)) = self.function_ahead() else {
            let word: String = self.peek_word(6);
            return Err(self.err(format!(
                "unknown function or word '{word}…' where a value should be"
            )));
        };
        self.take(len);
        self.take(1); // '['
        if name == "exists" {
            if self.peek() != Some('#') {
                return Err(self.err("EXISTS takes a parameter: EXISTS[#<name>]"));
            }
            self.take(1);
            let p = self.param_name()?;
            if self.peek() != Some(']') {
                return Err(self.err("EXISTS[#<name>] is missing its ']'"));
            }
            self.take(1);
            return Ok(Expr::Exists(Box::new(p)));
        }
        let arg = self.expression()?;
        if name == "atan" {
            if self.peek() != Some('/') {
                return Err(self.err("ATAN needs two arguments: ATAN[y]/[x]"));
            }
            self.take(1);
            if self.peek() != Some('[') {
                return Err(self.err("ATAN needs two arguments: ATAN[y]/[x]"));
            }
            self.take(1);
            let x = self.expression()?;
            return Ok(Expr::Atan(Box::new(arg), Box::new(x)));
        }
        let f = match name {
            "abs" => Func::Abs,
            "acos" => Func::Acos,
            "asin" => Func::Asin,
            "cos" => Func::Cos,
            "exp" => Func::Exp,
            "fix" => Func::Fix,
            "fup" => Func::Fup,
            "ln" => Func::Ln,
            "round" => Func::Round,
            "sin" => Func::Sin,
            "sqrt" => Func::Sqrt,
            _ => Func::Tan,
        };
        Ok(Expr::Func(f, Box::new(arg)))
    }

    /// After `[`: operands and operators up to the matching `]` (consumed).
    pub(super) fn expression(&mut self) -> Result<Expr, ParseError> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(self.err(format!("expression nested deeper than {MAX_DEPTH} levels")));
        }
        let e = self.binary(1)?;
        match self.peek() {
            Some(']') => self.take(1),
            None => return Err(self.err("expression '[' is not closed by ']'")),
            Some(c) => return Err(self.err(format!("unknown operator {c:?} in an expression"))),
        }
        self.depth -= 1;
        Ok(e)
    }

    fn binary(&mut self, min: u8) -> Result<Expr, ParseError> {
        let mut left = self.value()?;
        while let Some((op, len)) = self.operator_ahead() {
            if op.precedence() < min {
                break;
            }
            self.take(len);
            let right = self.binary(op.precedence() + 1)?;
            left = Expr::Binary(op, Box::new(left), Box::new(right));
        }
        Ok(left)
    }

    fn operator_ahead(&mut self) -> Option<(Op, usize)> {
        self.skip_blanks();
        let ahead = self.peek_word(3);
        const OPS: [(&str, Op); 15] = [
            ("**", Op::Power),
            ("*", Op::Times),
            ("/", Op::Divide),
            ("+", Op::Plus),
            ("-", Op::Minus),
            ("and", Op::And),
            ("mod", Op::Modulo),
            ("xor", Op::Xor),
            ("or", Op::Or),
            ("eq", Op::Eq),
            ("ne", Op::Ne),
            ("gt", Op::Gt),
            ("ge", Op::Ge),
            ("lt", Op::Lt),
            ("le", Op::Le),
        ];
        OPS.iter()
            .find(|(s, _)| ahead.starts_with(*s))
            .map(|(s, op)| (*op, s.len()))
    }

    /// A number: optional sign, digits with at most one `.` (blanks allowed between them).
    pub(super) fn number(&mut self) -> Result<f64, ParseError> {
        let start = self.at;
        let mut text = String::new();
        let mut digits = 0usize;
        let mut dot = false;
        if let Some(s @ ('+' | '-')) = self.peek() {
            text.push(s);
            self.take(1);
        }
        loop {
            match self.peek() {
                Some(d) if d.is_ascii_digit() => {
                    text.push(d);
                    digits += 1;
                }
                Some('.') if !dot => {
                    text.push('.');
                    dot = true;
                }
                _ => break,
            }
            self.take(1);
        }
        if digits == 0 {
            self.at = start;
            return Err(self.err("a number is missing"));
        }
        if digits > 40 {
            return Err((start, "a number with more than 40 digits".into()));
        }
        let value: f64 = text
            .parse()
            .map_err(|_| (start, format!("bad number {text}")))?;
        if value.abs() > MAX_MAGNITUDE {
            return Err((start, format!("number {text} is too large")));
        }
        Ok(value)
    }
}

/// Evaluate an expression.
///
/// # Errors
/// A message for a division by zero, a function outside its domain, a result that is not
/// finite, an undefined named parameter or a parameter number out of range.
pub(super) fn eval(e: &Expr, p: &dyn ParamSource) -> Result<f64, String> {
    let v = match e {
        Expr::Number(v) => *v,
        Expr::Numbered(i) => {
            let i = param_index(eval(i, p)?)?;
            p.numbered(i)?
        }
        Expr::Named(n) => p
            .named(n)
            .ok_or_else(|| format!("named parameter #<{n}> is not defined"))?,
        Expr::Exists(name) => match name.as_ref() {
            ParamName::Named(n) => f64::from(u8::from(p.named(n).is_some())),
            ParamName::Numbered(i) => {
                let i = eval(i, p)?;
                f64::from(u8::from(i >= 1.0 && i < PARAMETER_LIMIT as f64))
            }
        },
        Expr::Neg(v) => -eval(v, p)?,
        Expr::Func(f, v) => func(*f, eval(v, p)?)?,
        Expr::Atan(y, x) => eval(y, p)?.atan2(eval(x, p)?).to_degrees(),
        Expr::Binary(op, l, r) => binary(*op, eval(l, p)?, eval(r, p)?)?,
    };
    if v.is_finite() {
        Ok(v)
    } else {
        Err("calculation result is not a finite number".into())
    }
}

/// A parameter number from a value: an integer within 0.0001 (LinuxCNC's rule), 1 ..= 5601.
///
/// # Errors
/// A message for a value that is not an integer or out of range.
pub(super) fn param_index(v: f64) -> Result<usize, String> {
    let i = integer(v).ok_or_else(|| format!("parameter number {v} is not an integer"))?;
    if (1..PARAMETER_LIMIT as i64).contains(&i) {
        Ok(usize::try_from(i).unwrap_or(0))
    } else {
        Err(format!(
            "parameter number {i} is out of range (#1..#{})",
            PARAMETER_LIMIT - 1
        ))
    }
}

/// An integer within 0.0001, as LinuxCNC's `read_integer_value` accepts it.
pub(super) fn integer(v: f64) -> Option<i64> {
    if !v.is_finite() || v.abs() > 1e15 {
        return None;
    }
    let f = v.floor();
    let frac = v - f;
    if frac > 0.9999 {
        Some(v.ceil() as i64)
    } else if frac > 0.0001 {
        None
    } else {
        Some(f as i64)
    }
}

fn func(f: Func, v: f64) -> Result<f64, String> {
    Ok(match f {
        Func::Abs => v.abs(),
        Func::Acos | Func::Asin => {
            if !(-1.0..=1.0).contains(&v) {
                let name = if f == Func::Acos { "ACOS" } else { "ASIN" };
                return Err(format!("{name} of {v} (outside -1..1)"));
            }
            if f == Func::Acos {
                v.acos().to_degrees()
            } else {
                v.asin().to_degrees()
            }
        }
        Func::Cos => v.to_radians().cos(),
        Func::Sin => v.to_radians().sin(),
        Func::Tan => v.to_radians().tan(),
        Func::Exp => v.exp(),
        Func::Fix => v.floor(),
        Func::Fup => v.ceil(),
        Func::Ln => {
            if v <= 0.0 {
                return Err(format!("LN of {v} (not positive)"));
            }
            v.ln()
        }
        Func::Round => (v + if v < 0.0 { -0.5 } else { 0.5 }).trunc(),
        Func::Sqrt => {
            if v < 0.0 {
                return Err(format!("SQRT of {v} (negative)"));
            }
            v.sqrt()
        }
    })
}

fn binary(op: Op, l: f64, r: f64) -> Result<f64, String> {
    let truth = |b: bool| f64::from(u8::from(b));
    Ok(match op {
        Op::And => truth(l != 0.0 && r != 0.0),
        Op::Or => truth(l != 0.0 || r != 0.0),
        Op::Xor => truth((l != 0.0) != (r != 0.0)),
        Op::Eq => truth((l - r).abs() < TOLERANCE_EQUAL),
        Op::Ne => truth((l - r).abs() >= TOLERANCE_EQUAL),
        Op::Gt => truth(l > r),
        Op::Ge => truth(l >= r),
        Op::Lt => truth(l < r),
        Op::Le => truth(l <= r),
        Op::Plus => l + r,
        Op::Minus => l - r,
        Op::Times => l * r,
        Op::Divide => {
            if r == 0.0 {
                return Err("division by zero".into());
            }
            l / r
        }
        Op::Modulo => {
            let m = l % r;
            if m < 0.0 { m + r.abs() } else { m }
        }
        Op::Power => {
            if l < 0.0 && r.floor() != r {
                return Err(format!(
                    "{l} to the power {r} (a negative number to a fractional power)"
                ));
            }
            l.powf(r)
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn value_of(text: &str) -> Result<f64, String> {
        let chars: Vec<char> = text.chars().collect();
        let mut r = Reader::new(&chars, 0);
        let e = r.value().map_err(|(_, m)| m)?;
        eval(&e, &NoParams)
    }

    #[test]
    fn precedence_and_linuxcnc_rules() {
        let cases = [
            ("[1 + 2 * 3]", 7.0),
            ("[2**3**2]", 64.0),
            ("[-2**2]", 4.0),
            ("[1 + 2 * 3 GT 6 AND 1]", 1.0),
            ("[10 MOD -3]", 1.0),
            ("[-7 MOD 3]", 2.0),
            ("ATAN[1]/[1]", 45.0),
            ("[ROUND[-2.5]]", -3.0),
            ("FIX[-2.5]", -3.0),
            ("FUP[-2.5]", -2.0),
            ("-[1+2]", -3.0),
            ("[1 EQ 1.00005]", 1.0),
            ("[1 NE 1.001]", 1.0),
            ("[2 xor 0]", 1.0),
            ("[sin[30] * 2]", 1.0),
            ("[ 1 - 2 - 3 ]", -4.0),
            ("[8 / 2 / 2]", 2.0),
            ("EXISTS[#<nothing>]", 0.0),
            ("[#1 + 1]", 1.0),
        ];
        for (text, want) in cases {
            let got = value_of(text).unwrap();
            assert!((got - want).abs() < 1e-12, "{text}: {got} != {want}");
        }
    }

    #[test]
    fn errors() {
        for (text, what) in [
            ("[1/0]", "division"),
            ("SQRT[-1]", "SQRT"),
            ("[1 + ]", "number"),
            ("[1 + 2", "not closed"),
            ("#<x>", "not defined"),
            (
                "[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[1]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]",
                "nested",
            ),
            ("ATAN[1]", "two arguments"),
            ("[-2 ** 0.5]", "fractional"),
            ("#6000", "out of range"),
            ("#1.5", "not an integer"),
        ] {
            let e = value_of(text).unwrap_err();
            assert!(e.contains(what), "{text}: {e}");
        }
    }
}
