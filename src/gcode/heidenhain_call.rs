//! One Heidenhain cycle definition as the interpreter keeps it until a call (`G79`, `M99`,
//! `M89`): its own file so that the interpreter's state can hold it without using the cycle
//! reader ([`super::heidenhain`]), which uses the state.

/// A defined Heidenhain drilling cycle (`G200 Q200=2 Q201=-7 …`): its number and its Q
/// parameters, in program units (feeds per minute; [`f64::INFINITY`] for `FMAX`).
#[derive(Clone, Debug, PartialEq)]
pub(super) struct HeidenhainCycle {
    /// 200, 201, 202, 203, 205, 207 or 209.
    pub(super) number: u32,
    /// `(Q number, value)` in the order given.
    pub(super) q: Vec<(u32, f64)>,
}

impl HeidenhainCycle {
    /// The value of `Qn`.
    pub(super) fn get(&self, n: u32) -> Option<f64> {
        self.q.iter().find(|(k, _)| *k == n).map(|(_, v)| *v)
    }

    /// `Gnnn`.
    pub(super) fn name(&self) -> String {
        format!("G{}", self.number)
    }
}
