//! One Sinumerik drilling cycle call as the interpreter keeps it (modal under MCALL): its own
//! file so that the interpreter's state can hold it without using the cycle reader
//! ([`super::siemens`]), which uses the state.

/// Which Sinumerik drilling cycle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Kind {
    Drill,
    Dwell,
    Deep,
    Tap,
    Bore,
    BoreStop,
}

/// One Sinumerik drilling cycle call with its parameters, in program units.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct SiemensCycle {
    pub(super) name: String,
    pub(super) kind: Kind,
    pub(super) rtp: f64,
    pub(super) rfp: f64,
    pub(super) sdis: f64,
    pub(super) dp: f64,
    pub(super) dtb: f64,
    /// CYCLE83: first depth, degression, dwell at the start point, VARI.
    pub(super) fdep: Option<f64>,
    pub(super) dam: f64,
    pub(super) dts: f64,
    pub(super) chip_break: bool,
    /// CYCLE85: feed in and out (None: the modal F).
    pub(super) ffr: Option<f64>,
    pub(super) rff: Option<f64>,
}
