//! RS274NGC parameters as LinuxCNC keeps them.
//!
//! - Numbered `#1` .. `#5601`: `#1`..`#30` are a subroutine's arguments (saved by `call` and
//!   restored by `return`/`endsub`), `#31`..`#5160` are global; a parameter never set reads 0.
//!   `#5161`..`#5601` belong to the controller and are read-only here: `#5161`–`#5169` the
//!   G28 home, `#5210`–`#5219` the G92/G52 offset, `#5220` the coordinate system (1 = G54),
//!   `#5221`.. the G54..G59.3 offsets (20 a system), `#5400` the tool in the spindle,
//!   `#5401`–`#5409` its length offset, `#5410` its diameter, `#5420`–`#5428` the current
//!   position in program coordinates (all in program units).
//! - Named `#<name>` are local to the subroutine (or the main program) that sets them;
//!   `#<_name>` (leading underscore) are global. Reading a named parameter never set is an
//!   error. Predefined read-only globals: `#<_x>`..`#<_c>` (the position, as `#5420`..),
//!   `#<_feed>`, `#<_rpm>`, `#<_current_tool>`, `#<_selected_tool>`, `#<_metric>`,
//!   `#<_imperial>`, `#<_absolute>`, `#<_incremental>`, `#<_inverse_time>`,
//!   `#<_units_per_minute>`, `#<_plane>` (170/180/190), `#<_motion_mode>` (code × 10),
//!   `#<_ccomp>` (400/410/420), `#<_coord_system>` (540..), `#<_tool_offset>`,
//!   `#<_retract_r_plane>`, `#<_retract_old_z>`, `#<_line>`; `#<_value>` and
//!   `#<_value_returned>` after a subroutine returns a value.
//! - Values set on a line take effect after the whole line is read.

use std::collections::BTreeMap;

use super::expr::PARAMETER_LIMIT;

/// Subroutine arguments `#1`..`#30`.
pub(super) const SUB_ARGS: usize = 30;
/// First controller parameter (read-only here).
pub(super) const FIRST_SYSTEM: usize = 5161;
/// Deepest subroutine nesting (LinuxCNC's `INTERP_SUB_ROUTINE_LEVELS`).
pub(super) const MAX_CALL_DEPTH: usize = 10;

/// The parameter store.
#[derive(Clone, Debug)]
pub(super) struct Params {
    numbered: Vec<f64>,
    globals: BTreeMap<String, f64>,
    /// Local named parameters, one map per call level (`[0]` is the main program).
    locals: Vec<BTreeMap<String, f64>>,
    /// `#1`..`#30` of each caller, restored on return.
    saved: Vec<[f64; SUB_ARGS]>,
}

impl Default for Params {
    fn default() -> Self {
        Self {
            numbered: vec![0.0; PARAMETER_LIMIT],
            globals: BTreeMap::new(),
            locals: vec![BTreeMap::new()],
            saved: Vec::new(),
        }
    }
}

impl Params {
    /// A numbered parameter's stored value (0 when never set or out of range).
    pub(super) fn get(&self, index: usize) -> f64 {
        self.numbered.get(index).copied().unwrap_or(0.0)
    }

    /// Set a numbered parameter.
    ///
    /// # Errors
    /// A message for a controller parameter (`#5161` and above).
    pub(super) fn set(&mut self, index: usize, value: f64) -> Result<(), String> {
        if index >= FIRST_SYSTEM {
            return Err(format!(
                "parameter #{index} belongs to the controller (offsets, tool, position) and is \
                 read-only here: set offsets with G10, G52 or G92"
            ));
        }
        if let Some(slot) = self.numbered.get_mut(index) {
            *slot = value;
        }
        Ok(())
    }

    /// A named parameter set by the program (global for `_name`, else the current level's).
    pub(super) fn named(&self, name: &str) -> Option<f64> {
        if name.starts_with('_') {
            self.globals.get(name).copied()
        } else {
            self.locals.last().and_then(|l| l.get(name)).copied()
        }
    }

    /// Set a named parameter.
    pub(super) fn set_named(&mut self, name: &str, value: f64) {
        if name.starts_with('_') {
            self.globals.insert(name.to_string(), value);
        } else if let Some(l) = self.locals.last_mut() {
            l.insert(name.to_string(), value);
        }
    }

    /// Call depth (0 in the main program).
    pub(super) fn depth(&self) -> usize {
        self.saved.len()
    }

    /// Enter a subroutine: save `#1`..`#30`, set them to the arguments (0 beyond them), open
    /// a new level of local names.
    ///
    /// # Errors
    /// A message when more than 30 arguments are given or the nesting is too deep.
    pub(super) fn call(&mut self, args: &[f64]) -> Result<(), String> {
        if args.len() > SUB_ARGS {
            return Err(format!(
                "a call passes at most {SUB_ARGS} arguments, not {}",
                args.len()
            ));
        }
        if self.saved.len() >= MAX_CALL_DEPTH {
            return Err(format!(
                "subroutines nested deeper than {MAX_CALL_DEPTH} levels"
            ));
        }
        let mut saved = [0.0; SUB_ARGS];
        for (i, slot) in saved.iter_mut().enumerate() {
            let p = self.numbered.get_mut(i + 1);
            if let Some(p) = p {
                *slot = *p;
                *p = args.get(i).copied().unwrap_or(0.0);
            }
        }
        self.saved.push(saved);
        self.locals.push(BTreeMap::new());
        self.globals.insert("_value_returned".into(), 0.0);
        Ok(())
    }

    /// Leave a subroutine: restore the caller's `#1`..`#30` and drop the local names;
    /// `value` is what `return [..]`/`endsub [..]` gave (`#<_value>`).
    pub(super) fn ret(&mut self, value: Option<f64>) {
        if let Some(saved) = self.saved.pop() {
            for (i, v) in saved.iter().enumerate() {
                if let Some(p) = self.numbered.get_mut(i + 1) {
                    *p = *v;
                }
            }
            self.locals.pop();
        }
        self.globals.insert("_value".into(), value.unwrap_or(0.0));
        self.globals.insert(
            "_value_returned".into(),
            f64::from(u8::from(value.is_some())),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn calls_save_and_restore_arguments_and_locals() {
        let mut p = Params::default();
        p.set(1, 7.0).unwrap();
        p.set(31, 3.0).unwrap();
        p.set_named("depth", 2.0);
        p.set_named("_g", 5.0);
        p.call(&[1.0, 2.0]).unwrap();
        assert_eq!(
            (p.get(1), p.get(2), p.get(3), p.get(31)),
            (1.0, 2.0, 0.0, 3.0)
        );
        assert_eq!(p.named("depth"), None);
        assert_eq!(p.named("_g"), Some(5.0));
        p.set_named("depth", 9.0);
        p.ret(Some(42.0));
        assert_eq!((p.get(1), p.get(2)), (7.0, 0.0));
        assert_eq!(p.named("depth"), Some(2.0));
        assert_eq!(p.named("_value"), Some(42.0));
        assert!(p.set(5221, 1.0).is_err());
        for _ in 0..MAX_CALL_DEPTH {
            p.call(&[]).unwrap();
        }
        assert!(p.call(&[]).is_err());
    }
}
