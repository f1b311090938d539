//! The real-time step contract, owned by `session::RealtimeSession` (issue 18): the scripted input
//! of `data/golden/realtime/` gives `expected.csv` exactly; an absurd input is refused or rolled
//! back with its reason and leaves the session unchanged; the one state format continues bit for
//! bit and refuses a state from another configuration, a truncated one or a flipped byte.

use pcsim_core::presets;
use pcsim_core::session::{Coupling, RealtimeSession, Refusal};

fn root() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn session() -> RealtimeSession {
    let (case, _) = presets::load("syt-7.0-9.8").unwrap();
    RealtimeSession::new(&case, 215.0, Coupling::Hil).unwrap()
}

fn script() -> Vec<[f64; 3]> {
    std::fs::read_to_string(root().join("data/golden/realtime/script.csv"))
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|s| s.parse().unwrap()).collect();
            [v[0], v[1], v[2]]
        })
        .collect()
}

#[test]
fn the_script_gives_the_golden_statuses_and_outputs() {
    let golden = std::fs::read_to_string(root().join("data/golden/realtime/expected.csv")).unwrap();
    let mut rt = session();
    let x0 = rt.start_position_m();
    let mut got = String::from("row,status,time_s,wire_height_m,wire_velocity_m_s\n");
    for (k, r) in script().iter().enumerate() {
        match rt.step(r[1], x0 + r[2]) {
            Ok(o) => got.push_str(&format!(
                "{k},ok,{:?},{:?},{:?}\n",
                o.time_s, o.wire_height_m, o.wire_velocity_m_s
            )),
            Err(e) => got.push_str(&format!("{k},{},,,\n", e.code())),
        }
    }
    assert_eq!(got, golden);
    assert_eq!(rt.moves(), 3);
    // Five refusals: every other row was stepped.
    assert_eq!(rt.steps(), 4000 - 5);
}

#[test]
fn an_absurd_force_is_refused_everywhere_and_rolled_back_beyond_the_bound() {
    let mut rt = session();
    let x0 = rt.start_position_m();
    for k in 0..200 {
        rt.step(85.0, x0 + 0.06 * k as f64).unwrap();
    }
    let before = RealtimeSession::state_bytes(&rt.state([0.0; 4]));
    for f in [1e300, -1e300, f64::NAN, f64::INFINITY, 1e6] {
        let e = rt.step(f, x0 + 12.0).unwrap_err();
        assert!(matches!(e, Refusal::Input(_)), "{f}: {e}");
        assert!(
            ["force_out_of_bound", "not_finite"].contains(&e.code()),
            "{f}: {e}"
        );
    }
    assert_eq!(RealtimeSession::state_bytes(&rt.state([0.0; 4])), before);
    // With the bound lifted, 1e300 N is stepped, found unsound and rolled back.
    rt.set_force_limit_n(1e301).unwrap();
    let e = rt.step(1e300, x0 + 12.0).unwrap_err();
    assert_eq!(e.code(), "rolled_back", "{e}");
    assert_eq!(RealtimeSession::state_bytes(&rt.state([0.0; 4])), before);
    assert!(rt.set_force_limit_n(f64::NAN).is_err());
    // The session goes on as if nothing had happened.
    let o = rt.step(85.0, x0 + 12.0).unwrap();
    assert!(o.wire_height_m.abs() < 0.5, "{o:?}");
}

#[test]
fn the_state_format_continues_bit_for_bit_and_refuses_damage() {
    let mut a = session();
    let x0 = a.start_position_m();
    for k in 0..1500 {
        a.step(85.0, x0 + 0.0617 * k as f64).unwrap();
    }
    let bytes = RealtimeSession::state_bytes(&a.state([1.0, 2.0, 3.0, 4.0]));
    assert_eq!(bytes.len(), a.state_size());
    let mut b = session();
    let s = b.state_from_bytes(&bytes).unwrap();
    assert_eq!(s.host, [1.0, 2.0, 3.0, 4.0]);
    b.restore(&s).unwrap();
    for k in 1500..2000 {
        let x = x0 + 0.0617 * k as f64;
        assert_eq!(a.step(90.0, x).unwrap(), b.step(90.0, x).unwrap());
    }
    // Every single flipped byte is refused (a sample of positions through the whole blob).
    for i in (0..bytes.len())
        .step_by(97)
        .chain([bytes.len() - 1, 9, 17, 25])
    {
        let mut d = bytes.clone();
        d[i] ^= 0x10;
        assert!(b.state_from_bytes(&d).is_err(), "byte {i} flipped");
    }
    assert!(b.state_from_bytes(&bytes[..bytes.len() - 1]).is_err());
    assert!(b.state_from_bytes(&[]).is_err());
    // Another configuration's state.
    let (case, _) = presets::load("syt-7.0-9.8").unwrap();
    let other = RealtimeSession::new(&case, 240.0, Coupling::Hil).unwrap();
    let e = other.state_from_bytes(&bytes).unwrap_err();
    assert!(e.contains("another configuration"), "{e}");
}

#[test]
fn the_window_carries_the_leading_pantograph_only() {
    // stitched-2018-like runs two pantographs; the session keeps the leading one.
    let (case, _) = presets::load("stitched-2018-like").unwrap();
    assert!(case.pantographs.len() > 1);
    let mut rt = RealtimeSession::new(&case, 240.0, Coupling::Sil).unwrap();
    let o = rt.step(0.0, 0.0).unwrap();
    assert!(o.contact_force_n.is_finite());
    let mut one = case.clone();
    one.pantographs.truncate(1);
    let mut rt1 = RealtimeSession::new(&one, 240.0, Coupling::Sil).unwrap();
    assert_eq!(rt1.step(0.0, 0.0).unwrap(), o);
    // The bare window keeps the leading one too (`compile::window_case`, one place) ...
    let bare = pcsim_core::compile::realtime_window(&case, 240.0, Coupling::Sil).unwrap();
    assert_eq!(bare.model().pantographs.len(), 1);
    // ... and the window's constructor refuses a full model with two, naming the field.
    let full = pcsim_core::compile::Setup::from_case(&case).unwrap();
    let e = pcsim_core::solve::realtime::RealtimeCatenary::new(
        &full.model,
        &full.plan,
        full.options,
        case.catenary.span_m,
        100.0,
        240.0,
        Coupling::Sil,
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("pantographs") && e.contains("one pantograph"),
        "{e}"
    );
}

/// On a line (issue 21, item 7) the window is a model per position, so a saved state carries its
/// position: a state saved before the first overlap, restored into a fresh session after the
/// window has crossed it, continues bit for bit through both overlaps; every state fits the
/// size the session states; a state rolled back across a move continues as before.
#[test]
fn a_lines_state_carries_the_windows_position_across_the_overlaps() {
    let (case, _) = presets::load("en50318-2018-like-simple").unwrap();
    let new = || RealtimeSession::new(&case, 240.0, Coupling::Hil).unwrap();
    let mut a = new();
    let x0 = a.start_position_m();
    let dx = case.run.speed_kmh / 3.6 * a.dt_s();
    let x = |k: usize| x0 + dx * k as f64;
    let f = |k: usize| 140.0 + 30.0 * (0.01 * k as f64).sin();
    let until = |xe: f64| ((xe - x0) / dx) as usize;
    let k_save = until(500.0);
    for k in 0..k_save {
        a.step(f(k), x(k)).unwrap();
    }
    let size = a.state_size();
    let saved = a.state([0.0; 4]);
    let bytes = RealtimeSession::state_bytes(&saved);
    assert!(bytes.len() <= size, "{} > {size}", bytes.len());
    let moves_at_save = a.moves();
    // On past both overlaps, recording the outputs.
    let mut outputs = Vec::new();
    for k in k_save..until(1450.0) {
        outputs.push(a.step(f(k), x(k)).unwrap());
        let b = RealtimeSession::state_bytes(&a.state([0.0; 4]));
        assert!(
            b.len() <= size,
            "{} > {size} after {} moves",
            b.len(),
            a.moves()
        );
    }
    assert!(a.moves() >= moves_at_save + 8, "{} moves", a.moves());
    // A fresh session restored from the bytes, and the first one rolled back: both continue
    // as the first did.
    let mut b = new();
    b.restore(&b.state_from_bytes(&bytes).unwrap()).unwrap();
    a.restore(&saved).unwrap();
    assert_eq!(a.moves(), moves_at_save);
    for (i, k) in (k_save..until(1450.0)).enumerate() {
        assert_eq!(a.step(f(k), x(k)).unwrap(), outputs[i], "step {k}");
        assert_eq!(b.step(f(k), x(k)).unwrap(), outputs[i], "step {k}");
    }
}

/// Issue 41, item 4: the window follows the pantograph the rig represents
/// (`run.window_pantograph`). On `en50318-2018-like-simple` (a line of three tension lengths,
/// pantographs 200 m apart) the window of the trailing pantograph starts at its own position
/// (the leading one's less its offset) and steps, through the overlaps, exactly as the window of
/// a case whose only pantograph is that one (the same bytes in SIL); by name and by index the
/// same; a selection the case does not have is refused, naming the field and the pantographs.
#[test]
fn issue_41_4_the_window_follows_the_trailing_pantograph() {
    let (case, _) = presets::load("en50318-2018-like-simple").unwrap();
    assert_eq!(case.pantographs.len(), 2);
    let offset = case.pantographs[1].offset_m();
    assert!(offset > 100.0, "{offset}");
    let mut alone = case.clone();
    alone.pantographs.remove(0);
    let lead = RealtimeSession::new(&case, 240.0, Coupling::Sil).unwrap();
    let name = case.pantographs[1].name().to_string();
    for sel in ["trailing", name.as_str(), "1"] {
        let mut c = case.clone();
        c.run.window_pantograph = Some(sel.into());
        let mut rt = RealtimeSession::new(&c, 240.0, Coupling::Sil).unwrap();
        assert_eq!(
            rt.start_position_m(),
            lead.start_position_m() - offset,
            "{sel}"
        );
        let mut fresh = RealtimeSession::new(&alone, 240.0, Coupling::Sil).unwrap();
        let (x0, dx) = (rt.start_position_m(), c.speed_m_s() * rt.dt_s());
        let n = (600.0 / dx) as usize;
        for k in 0..n {
            let x = x0 + dx * (k + 1) as f64;
            assert_eq!(
                rt.step(0.0, x).unwrap(),
                fresh.step(0.0, x).unwrap(),
                "{sel} step {k}"
            );
        }
        assert!(rt.moves() >= 3, "{sel}: {} moves", rt.moves());
    }
    let mut c = case.clone();
    c.run.window_pantograph = Some("middle".into());
    let e = RealtimeSession::new(&c, 240.0, Coupling::Sil).unwrap_err();
    match e {
        pcsim_core::CaseError::Invalid { field, reason, .. } => {
            assert_eq!(field, "run.window_pantograph");
            assert!(reason.contains("leading, trailing"), "{reason}");
        }
        other => panic!("{other:?}"),
    }
    // The SIL window study of the trailing pantograph is measured against the full run of that
    // pantograph alone.
    let mut c = case.clone();
    c.run.window_pantograph = Some("trailing".into());
    let single = pcsim_core::compile::window_case(&c).unwrap();
    assert_eq!(single.pantographs, alone.pantographs);
}
