//! The state types the workstation owns and its panels show: what the properties panel is
//! focused on and the bottom dock's tab. Panels read them and return commands naming them;
//! they live here, not in a panel, so that commands, panels and the workstation each import
//! them from one place.

/// What the properties panel shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Focus {
    /// The part selection (the part or a face).
    #[default]
    Selection,
    /// Tool `i` of the project (its editor).
    Tool(usize),
    /// The stock.
    Stock,
    /// Setup `i` of the job (its frame, stock, workholding and operations).
    Setup(usize),
    /// Operation `i`.
    Operation(usize),
    /// The machine.
    Machine,
}

/// Which tab the bottom dock shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DockTab {
    /// The log.
    #[default]
    Log,
    /// A feature's tab, by its title (the posted program's "G-code" and "Motion", see
    /// [`super::feature::Feature::dock_tabs`]).
    Feature(&'static str),
}
