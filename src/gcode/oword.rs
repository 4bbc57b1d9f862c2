//! LinuxCNC O-words: subroutines, conditionals and loops.
//!
//! ```text
//! o100 sub            o<name> sub ... o<name> endsub [value]    definitions, anywhere in the file
//! o100 call [1] [2]   arguments become #1, #2, ... (up to #30) of the subroutine
//! o100 return [v]     leave early; [v] sets #<_value>
//! o1 if [c] / o1 elseif [c] / o1 else / o1 endif
//! o2 while [c] ... o2 endwhile         o3 do ... o3 while [c]
//! o4 repeat [n] ... o4 endrepeat       o2 break / o2 continue (in while and do loops)
//! ```
//!
//! Subroutine names are global; the labels of conditionals and loops are local to the
//! subroutine (or main program) they are in. The structure is checked before the program
//! runs: an `endif` without its `if`, a `break` outside its loop, a loop never closed or a
//! subroutine defined inside another is an error naming its line. A call of a subroutine
//! that is not in the program is an error (LinuxCNC would look for a file of that name on
//! its subroutine path; Talas reads one file).
//!
//! A program may execute at most [`MAX_ITERATIONS`] lines more than it has (the lines that
//! loops and calls run again); a program that spends that (a `while [1]` without a `break`)
//! ends with an error naming the line it reached, so hostile input cannot hang the
//! interpreter or fill the memory with moves.

use std::collections::BTreeMap;

use super::GcodeError;
use super::expr::{Expr, Reader, integer};

/// Lines a program may execute beyond its own length (in loops and calls).
pub const MAX_ITERATIONS: u64 = 1_000_000;

/// What an O-word line does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum OKind {
    Sub,
    EndSub,
    Call,
    Return,
    If,
    ElseIf,
    Else,
    EndIf,
    While,
    EndWhile,
    Do,
    Repeat,
    EndRepeat,
    Break,
    Continue,
}

impl OKind {
    fn from_name(name: &str) -> Option<Self> {
        Some(match name {
            "sub" => Self::Sub,
            "endsub" => Self::EndSub,
            "call" => Self::Call,
            "return" => Self::Return,
            "if" => Self::If,
            "elseif" => Self::ElseIf,
            "else" => Self::Else,
            "endif" => Self::EndIf,
            "while" => Self::While,
            "endwhile" => Self::EndWhile,
            "do" => Self::Do,
            "repeat" => Self::Repeat,
            "endrepeat" => Self::EndRepeat,
            "break" => Self::Break,
            "continue" => Self::Continue,
            _ => return None,
        })
    }

    fn name(self) -> &'static str {
        match self {
            Self::Sub => "sub",
            Self::EndSub => "endsub",
            Self::Call => "call",
            Self::Return => "return",
            Self::If => "if",
            Self::ElseIf => "elseif",
            Self::Else => "else",
            Self::EndIf => "endif",
            Self::While => "while",
            Self::EndWhile => "endwhile",
            Self::Do => "do",
            Self::Repeat => "repeat",
            Self::EndRepeat => "endrepeat",
            Self::Break => "break",
            Self::Continue => "continue",
        }
    }
}

/// An O-word line.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct OLine {
    /// `100` for `o100`, `<name>` for `o<name>` (lower case, no blanks).
    pub(super) name: String,
    pub(super) kind: OKind,
    /// The bracketed values after the keyword (call arguments, a condition, a count, a
    /// return value).
    pub(super) args: Vec<Expr>,
    /// 1-based column of the `o`.
    pub(super) column: usize,
}

impl OLine {
    /// `o100 if`, as messages name it.
    pub(super) fn label(&self) -> String {
        format!("o{} {}", self.name, self.kind.name())
    }
}

/// A parsed O-word line: the line, the value and column of an `N` word before it, and the
/// index after it.
pub(super) type ParsedOLine = (OLine, Option<(f64, usize)>, usize);

/// An O-word line starting at `start` (after block delete), with the value and column of an
/// `N` word before it, and the index after it; `None` when the line is not an O-word line (a
/// Fanuc program number `O1234` is not one).
///
/// # Errors
/// A [`GcodeError`] for a named O-word without a keyword, or a missing or malformed value.
pub(super) fn parse_oline(
    chars: &[char],
    start: usize,
    line: usize,
) -> Result<Option<ParsedOLine>, GcodeError> {
    let err = |i: usize, message: String| GcodeError {
        line,
        column: i + 1,
        message,
    };
    let mut r = Reader::new(chars, start);
    let mut n_word = None;
    if matches!(r.peek(), Some('n' | 'N')) {
        let column = r.at + 1;
        r.at += 1;
        match r.number() {
            Ok(v) => n_word = Some((v, column)),
            Err(_) => return Ok(None),
        }
    }
    if !matches!(r.peek(), Some('o' | 'O')) {
        return Ok(None);
    }
    let o_at = r.at;
    r.at += 1;
    let name = match r.peek() {
        Some('<') => {
            r.at += 1;
            let mut name = String::from("<");
            loop {
                match chars.get(r.at) {
                    Some('>') => {
                        r.at += 1;
                        break;
                    }
                    Some(c) if c.is_whitespace() => {}
                    Some(c) => name.push(c.to_ascii_lowercase()),
                    None => return Err(err(o_at, "O-word name '<' is not closed by '>'".into())),
                }
                r.at += 1;
            }
            name.push('>');
            name
        }
        Some(d) if d.is_ascii_digit() => {
            let Ok(v) = r.number() else {
                return Ok(None);
            };
            match integer(v) {
                Some(n) if n >= 0 => n.to_string(),
                _ => return Err(err(o_at, format!("O-word number {v} is not an integer"))),
            }
        }
        _ => return Ok(None),
    };
    let named = name.starts_with('<');
    let mut keyword = String::new();
    let _ = r.peek();
    while let Some(c) = chars.get(r.at)
        && c.is_ascii_alphabetic()
    {
        keyword.push(c.to_ascii_lowercase());
        r.at += 1;
    }
    let Some(kind) = OKind::from_name(&keyword) else {
        if named {
            return Err(err(
                o_at,
                format!(
                    "o{name} needs sub, endsub, call, return, if, elseif, else, endif, while, \
                     endwhile, do, repeat, endrepeat, break or continue"
                ),
            ));
        }
        return Ok(None); // a program number
    };
    let mut args = Vec::new();
    let bracket = |r: &mut Reader| -> Result<Option<Expr>, GcodeError> {
        if r.peek() == Some('[') {
            r.at += 1;
            r.expression().map(Some).map_err(|(at, m)| err(at, m))
        } else {
            Ok(None)
        }
    };
    match kind {
        OKind::Call => {
            while let Some(e) = bracket(&mut r)? {
                args.push(e);
            }
        }
        OKind::If | OKind::ElseIf | OKind::While | OKind::Repeat => {
            let Some(e) = bracket(&mut r)? else {
                return Err(err(
                    r.at,
                    format!("o{name} {keyword} needs its value in brackets: [ ... ]"),
                ));
            };
            args.push(e);
        }
        OKind::Return | OKind::EndSub => args.extend(bracket(&mut r)?),
        _ => {}
    }
    let oline = OLine {
        name,
        kind,
        args,
        column: o_at + 1,
    };
    Ok(Some((oline, n_word, r.at)))
}

/// How an O-word line links to the others.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Link {
    /// `sub`: the index of its `endsub`.
    Sub { end: usize },
    /// `if`/`elseif`/`else`: the next branch (or the `endif`) and the `endif`.
    Branch { next: usize, end: usize },
    /// `while`/`do`/`repeat`: the line that closes the loop.
    Head { tail: usize },
    /// `endwhile`, the `while` closing a `do`, `endrepeat`: the loop's first line.
    Tail { head: usize },
    /// `break`/`continue`: the loop they leave or restart.
    Jump { head: usize, tail: usize },
    /// `return`/`endsub` inside a definition, `endif`, `call`.
    Plain,
}

/// The O-word structure of a program, checked before it runs.
#[derive(Clone, Debug, Default)]
pub(super) struct Structure {
    links: BTreeMap<usize, Link>,
    /// Subroutine name → index of its `sub` line.
    subs: BTreeMap<String, usize>,
}

/// An open construct while the structure is read.
struct Open {
    at: usize,
    kind: OKind,
    label: String,
    branches: Vec<usize>,
}

/// Reads the O-word lines in order into a [`Structure`].
#[derive(Default)]
struct Builder {
    s: Structure,
    stack: Vec<Open>,
    /// The subroutine being defined.
    sub: Option<String>,
    /// Line index → source line number.
    lines: BTreeMap<usize, usize>,
}

impl Builder {
    fn line(&mut self, idx: usize, line: usize, o: &OLine) -> Result<(), GcodeError> {
        self.lines.insert(idx, line);
        let err = |message: String| GcodeError {
            line,
            column: o.column,
            message,
        };
        // Labels of conditionals and loops are local to their subroutine.
        let label = format!("{}#{}", self.sub.as_deref().unwrap_or(""), o.name);
        let open = |kind: OKind, label: String| Open {
            at: idx,
            kind,
            label,
            branches: vec![idx],
        };
        match o.kind {
            OKind::Sub => {
                if let Some(outer) = &self.sub {
                    return Err(err(format!(
                        "o{} sub inside the definition of o{outer}: subroutines cannot be nested",
                        o.name
                    )));
                }
                if self.s.subs.insert(o.name.clone(), idx).is_some() {
                    return Err(err(format!("subroutine o{} is defined twice", o.name)));
                }
                self.sub = Some(o.name.clone());
                self.stack.push(open(OKind::Sub, o.name.clone()));
            }
            OKind::EndSub => {
                let Some(at) = self.close(OKind::Sub, &o.name) else {
                    return Err(err(format!(
                        "o{} endsub does not close an open o{} sub (or a loop or if inside it is \
                         still open)",
                        o.name, o.name
                    )));
                };
                self.s.links.insert(at, Link::Sub { end: idx });
                self.s.links.insert(idx, Link::Plain);
                self.sub = None;
            }
            OKind::Return => {
                if self.sub.as_deref() != Some(o.name.as_str()) {
                    return Err(err(format!(
                        "o{} return is not inside the definition of o{} sub",
                        o.name, o.name
                    )));
                }
                self.s.links.insert(idx, Link::Plain);
            }
            OKind::Call => {
                self.s.links.insert(idx, Link::Plain);
            }
            OKind::If | OKind::Do | OKind::Repeat => self.stack.push(open(o.kind, label)),
            OKind::While => {
                let closes_do = self
                    .stack
                    .last()
                    .is_some_and(|t| t.kind == OKind::Do && t.label == label);
                if closes_do {
                    let head = self.close(OKind::Do, &label).unwrap_or(idx);
                    self.s.links.insert(head, Link::Head { tail: idx });
                    self.s.links.insert(idx, Link::Tail { head });
                } else {
                    self.stack.push(open(OKind::While, label));
                }
            }
            OKind::ElseIf | OKind::Else => {
                let top = self
                    .stack
                    .last_mut()
                    .filter(|t| t.kind == OKind::If && t.label == label);
                let Some(top) = top else {
                    return Err(err(format!("{} without an open o{} if", o.label(), o.name)));
                };
                top.branches.push(idx);
            }
            OKind::EndIf => {
                let open = self
                    .stack
                    .pop_if(|t| t.kind == OKind::If && t.label == label);
                let Some(open) = open else {
                    return Err(err(format!("{} without an open o{} if", o.label(), o.name)));
                };
                for (i, b) in open.branches.iter().enumerate() {
                    let next = open.branches.get(i + 1).copied().unwrap_or(idx);
                    self.s.links.insert(*b, Link::Branch { next, end: idx });
                }
                self.s.links.insert(idx, Link::Plain);
            }
            OKind::EndWhile | OKind::EndRepeat => {
                let want = if o.kind == OKind::EndWhile {
                    OKind::While
                } else {
                    OKind::Repeat
                };
                let Some(head) = self.close(want, &label) else {
                    return Err(err(format!(
                        "{} without an open o{} {}",
                        o.label(),
                        o.name,
                        want.name()
                    )));
                };
                self.s.links.insert(head, Link::Head { tail: idx });
                self.s.links.insert(idx, Link::Tail { head });
            }
            OKind::Break | OKind::Continue => {
                let found = self
                    .stack
                    .iter()
                    .rev()
                    .find(|t| t.label == label && matches!(t.kind, OKind::While | OKind::Do));
                let Some(found) = found else {
                    return Err(err(format!(
                        "{} is not inside an o{} while or o{} do loop",
                        o.label(),
                        o.name,
                        o.name
                    )));
                };
                // The tail is known once the loop closes: fixed up in `finish`.
                let head = found.at;
                self.s.links.insert(
                    idx,
                    Link::Jump {
                        head,
                        tail: usize::MAX,
                    },
                );
            }
        }
        Ok(())
    }

    /// Pop the innermost open construct if it is `kind` with `label`; its first line.
    fn close(&mut self, kind: OKind, label: &str) -> Option<usize> {
        self.stack
            .pop_if(|t| t.kind == kind && t.label == label)
            .map(|t| t.at)
    }

    fn finish(mut self) -> Result<Structure, GcodeError> {
        if let Some(open) = self.stack.last() {
            let line = self.lines.get(&open.at).copied().unwrap_or(0);
            let what = match open.kind {
                OKind::Sub => "endsub",
                OKind::If => "endif",
                OKind::While => "endwhile",
                OKind::Do => "while",
                _ => "endrepeat",
            };
            let name = open.label.rsplit('#').next().unwrap_or("");
            return Err(GcodeError {
                line,
                column: 1,
                message: format!(
                    "o{name} {} is never closed by o{name} {what}",
                    open.kind.name()
                ),
            });
        }
        let heads: BTreeMap<usize, usize> = self
            .s
            .links
            .iter()
            .filter_map(|(i, l)| match l {
                Link::Head { tail } => Some((*i, *tail)),
                _ => None,
            })
            .collect();
        for link in self.s.links.values_mut() {
            if let Link::Jump { head, tail } = link {
                *tail = heads.get(head).copied().unwrap_or(*head);
            }
        }
        Ok(self.s)
    }
}

impl Structure {
    /// Read the O-word lines (`olines`: line index, source line number and the O-line, in
    /// order).
    ///
    /// # Errors
    /// A [`GcodeError`] naming the line of a construct that does not match.
    pub(super) fn build(olines: &[(usize, usize, &OLine)]) -> Result<Self, GcodeError> {
        let mut b = Builder::default();
        for &(idx, line, o) in olines {
            b.line(idx, line, o)?;
        }
        b.finish()
    }

    /// The index of the `sub` line of subroutine `name`.
    pub(super) fn sub(&self, name: &str) -> Option<usize> {
        self.subs.get(name).copied()
    }

    /// Whether line `idx` lies inside a subroutine definition.
    pub(super) fn in_definition(&self, idx: usize) -> bool {
        self.links.iter().any(|(at, l)| match l {
            Link::Sub { end } => *at <= idx && idx <= *end,
            _ => false,
        })
    }
}

/// One subroutine call in progress.
#[derive(Clone, Debug)]
struct Frame {
    return_to: usize,
    /// Remaining iterations of the `repeat` loops running in this frame, by head index.
    repeats: BTreeMap<usize, i64>,
    /// The branch line the flow jumps to in order to test its condition.
    testing: Option<usize>,
}

/// Where the program goes after an O-word line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Step {
    /// Go on at this line index.
    Goto(usize),
    /// Enter subroutine: save the arguments, then go on at this index.
    Call(usize),
    /// Leave the subroutine with this value, going on at this index.
    Return(usize, Option<f64>),
}

/// The control-flow state of a running program.
#[derive(Clone, Debug, Default)]
pub(super) struct Flow {
    frames: Vec<Frame>,
}

impl Flow {
    fn frame(&mut self) -> &mut Frame {
        if self.frames.is_empty() {
            self.frames.push(Frame {
                return_to: usize::MAX,
                repeats: BTreeMap::new(),
                testing: None,
            });
        }
        let last = self.frames.len() - 1;
        &mut self.frames[last]
    }

    /// Execute O-word line `idx` (source line `line`). `value` evaluates the line's first
    /// bracketed value (a condition, a count, a return value), `args` all of them (a call's
    /// arguments); they are only read where the line needs them.
    ///
    /// # Errors
    /// A [`GcodeError`] for a call of an unknown subroutine, a spent budget, or a value that
    /// cannot be computed.
    pub(super) fn step(
        &mut self,
        idx: usize,
        line: usize,
        o: &OLine,
        structure: &Structure,
        value: &mut dyn FnMut() -> Result<Option<f64>, GcodeError>,
        in_call: bool,
    ) -> Result<Step, GcodeError> {
        let err = |message: String| GcodeError {
            line,
            column: o.column,
            message,
        };
        let link = structure.links.get(&idx).copied().unwrap_or(Link::Plain);
        let label = o.label();
        let next = idx + 1;
        let testing = self.frame().testing.take();
        Ok(match (o.kind, link) {
            (OKind::Sub, Link::Sub { end }) => Step::Goto(end + 1),
            (OKind::EndSub | OKind::Return, _) => {
                if !in_call {
                    return Err(err(format!("{label} outside a subroutine call")));
                }
                let v = value()?;
                let back = self.frames.pop().map_or(next, |f| f.return_to);
                Step::Return(back, v)
            }
            (OKind::Call, _) => {
                let Some(at) = structure.sub(&o.name) else {
                    return Err(err(format!(
                        "subroutine o{} is not defined in this program (subroutine files are \
                         not read)",
                        o.name
                    )));
                };
                self.frames.push(Frame {
                    return_to: next,
                    repeats: BTreeMap::new(),
                    testing: None,
                });
                Step::Call(at + 1)
            }
            (OKind::If, Link::Branch { next: other, .. }) => {
                if value()?.unwrap_or(0.0) != 0.0 {
                    Step::Goto(next)
                } else {
                    self.frame().testing = Some(other);
                    Step::Goto(other)
                }
            }
            (OKind::ElseIf, Link::Branch { next: other, end }) => {
                if testing != Some(idx) {
                    Step::Goto(end + 1) // a branch before this one ran
                } else if value()?.unwrap_or(0.0) != 0.0 {
                    Step::Goto(next)
                } else {
                    self.frame().testing = Some(other);
                    Step::Goto(other)
                }
            }
            (OKind::Else, Link::Branch { end, .. }) => {
                if testing == Some(idx) {
                    Step::Goto(next)
                } else {
                    Step::Goto(end + 1)
                }
            }
            (OKind::While, Link::Head { tail }) => {
                if value()?.unwrap_or(0.0) != 0.0 {
                    Step::Goto(next)
                } else {
                    Step::Goto(tail + 1)
                }
            }
            (OKind::While, Link::Tail { head }) => {
                // The end of a do loop.
                if value()?.unwrap_or(0.0) != 0.0 {
                    Step::Goto(head + 1)
                } else {
                    Step::Goto(next)
                }
            }
            (OKind::EndWhile, Link::Tail { head }) => Step::Goto(head),
            (OKind::Repeat, Link::Head { tail }) => {
                let v = value()?.unwrap_or(0.0);
                let n = integer(v.round()).unwrap_or(0);
                if n > 0 {
                    self.frame().repeats.insert(idx, n);
                    Step::Goto(next)
                } else {
                    Step::Goto(tail + 1)
                }
            }
            (OKind::EndRepeat, Link::Tail { head }) => {
                let frame = self.frame();
                let left = frame.repeats.get(&head).copied().unwrap_or(1) - 1;
                if left > 0 {
                    frame.repeats.insert(head, left);
                    Step::Goto(head + 1)
                } else {
                    frame.repeats.remove(&head);
                    Step::Goto(next)
                }
            }
            (OKind::Break, Link::Jump { tail, .. }) => Step::Goto(tail + 1),
            // A while loop re-tests at its head through its endwhile; a do loop at its
            // closing while.
            (OKind::Continue, Link::Jump { tail, .. }) => Step::Goto(tail),
            _ => Step::Goto(next),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn oline(text: &str) -> OLine {
        let chars: Vec<char> = text.chars().collect();
        parse_oline(&chars, 0, 1).unwrap().unwrap().0
    }

    #[test]
    fn parses_names_keywords_and_arguments() {
        let o = oline("N10 o<Drill Hole> call [1] [2.5] [#1]");
        assert_eq!(
            (o.name.as_str(), o.kind, o.args.len(), o.column),
            ("<drillhole>", OKind::Call, 3, 5)
        );
        let o = oline("O0100 IF [#1 GT 2]");
        assert_eq!(
            (o.name.as_str(), o.kind, o.args.len()),
            ("100", OKind::If, 1)
        );
        let chars: Vec<char> = "O1234 (program number)".chars().collect();
        assert!(parse_oline(&chars, 0, 1).unwrap().is_none());
        let chars: Vec<char> = "o100 while".chars().collect();
        assert!(parse_oline(&chars, 0, 1).is_err());
    }

    #[test]
    fn structure_errors_name_the_line() {
        let lines = [oline("o1 if [1]"), oline("o2 endif")];
        let refs: Vec<(usize, usize, &OLine)> = lines
            .iter()
            .enumerate()
            .map(|(i, o)| (i, i + 1, o))
            .collect();
        let e = Structure::build(&refs).unwrap_err();
        assert_eq!(e.line, 2);
        let lines = [oline("o1 while [1]")];
        let refs: Vec<(usize, usize, &OLine)> = lines
            .iter()
            .enumerate()
            .map(|(i, o)| (i, i + 1, o))
            .collect();
        let e = Structure::build(&refs).unwrap_err();
        assert!(e.message.contains("never closed"), "{}", e.message);
    }
}
