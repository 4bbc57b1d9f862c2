//! The operator panel's active codes during a feed hold (issue 35, "numbers that disagree"):
//! after an MDI `S2000 M4` (then `M5`) the program runs with `M3 S8000`; held in its fed
//! move, the control reports the program's modal state at the line it stopped in (M3,
//! S8000, G1, its F), not the MDI session's (M5, S2000). Before, a hold fell back to the
//! MDI state, because the held blocks were not counted as the running block.

use talas::control::{Action, Control, ControlConfig, Mode, RunState};
use talas::machine::Machine;

const PROGRAM: &str = "G21 G90 G17 G54\nG40 G49\nM3 S8000\nG0 X0 Y0 Z50\nG1 Z40 F300\n\
G1 X150 F900\nG0 Z90\nM30\n";

fn run_for(c: &mut Control, seconds: f64) {
    let dt = 0.01;
    let mut t = 0.0;
    while t < seconds {
        c.advance(dt);
        t += dt;
    }
}

#[test]
fn a_held_program_shows_its_own_active_codes_not_the_mdi_state() {
    let m = Machine::builtin("mill-3axis").unwrap();
    let mut c = Control::new(ControlConfig::new(m)).unwrap();
    c.apply(Action::Home).unwrap();
    run_for(&mut c, 60.0);
    c.apply(Action::SetMode(Mode::Mdi)).unwrap();
    c.apply(Action::Mdi("S2000 M4".into())).unwrap();
    run_for(&mut c, 2.0);
    let mdi = c.snapshot().active_codes;
    assert!(
        mdi.contains(&"S2000".to_string()) && mdi.contains(&"M4".to_string()),
        "{mdi:?}"
    );
    c.apply(Action::Mdi("M5".into())).unwrap();
    run_for(&mut c, 1.0);

    c.apply(Action::SetMode(Mode::Auto)).unwrap();
    c.apply(Action::LoadProgram {
        name: "hold.ngc".into(),
        text: PROGRAM.into(),
    })
    .unwrap();
    c.apply(Action::CycleStart).unwrap();
    // Run until the fed X move is under way, then hold.
    let mut guard = 0;
    while c.snapshot().line != Some(6) {
        c.advance(0.01);
        guard += 1;
        assert!(guard < 20_000, "the program never reached line 6");
    }
    run_for(&mut c, 0.5);
    let running = c.snapshot().active_codes;
    c.apply(Action::FeedHold).unwrap();
    run_for(&mut c, 1.0);
    let snap = c.snapshot();
    assert_eq!(snap.state, RunState::Held);
    let held = snap.active_codes;
    for code in ["M3", "G1", "S8000", "F900"] {
        assert!(
            held.iter().any(|c| c == code),
            "{code} missing while held: {held:?}"
        );
    }
    for code in ["M5", "M4", "S2000"] {
        assert!(
            !held.iter().any(|c| c == code),
            "{code} (MDI) shown while held: {held:?}"
        );
    }
    assert_eq!(held, running, "holding does not change the active codes");
    assert_eq!(snap.line, Some(6), "the held line");
}
