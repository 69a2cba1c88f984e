//! Roof loads (paper §3.2–3.3) on short runs: the impact time, and the trends of Fig. 8 and
//! Fig. 10. Trends are compared between runs of the same scheme, so no tolerance is needed
//! beyond the sign of the difference; each test prints the numbers.

use slosh_validation::{out_dir, run_script};

/// Paper §3.2, tank height 0.6 m: a roof impact whose peak comes between 1.3 s and 2.0 s
/// after the excitation starts (the paper: 1.61 s); the script's `post` results land in the
/// summary.
#[test]
fn roof_impact_at_the_paper_time() {
    let out = out_dir("roof_0.60");
    let s = run_script("paper_2d_roof.rhai", &["tank_height=0.6"], &out).unwrap();
    let after = s.t_max_roof_p - s.settle;
    eprintln!(
        "tank 0.60 m: max roof p {:.0} Pa at {after:.3} s after the excitation start, max roof force {:.1} N/m, Kurihara {:.0} Pa, Malhotra {:.0} Pa",
        s.max_roof_p, s.max_roof_force_up, s.kurihara_at_max, s.malhotra_at_max
    );
    assert!(s.max_roof_p > 0.0 && s.max_roof_force_up > 0.0);
    assert!((1.3..=2.0).contains(&after), "peak at {after} s");
    assert!(!s.impacts.is_empty());
    for key in ["roof_impulse", "time_above_threshold", "peak_over_kurihara"] {
        assert!(
            s.post.iter().any(|(k, _)| k == key),
            "post result {key} missing"
        );
    }
    assert!(out.join("roof_pressure.csv").exists());
}

/// Fig. 8 trend: the lower roof (0.56 m) carries a larger peak roof force than the higher
/// one (0.66 m).
#[test]
fn peak_roof_force_decreases_with_tank_height() {
    let low = run_script(
        "paper_2d_roof.rhai",
        &["tank_height=0.56"],
        &out_dir("roof_0.56"),
    )
    .unwrap();
    let high = run_script(
        "paper_2d_roof.rhai",
        &["tank_height=0.66"],
        &out_dir("roof_0.66"),
    )
    .unwrap();
    eprintln!(
        "peak roof force: 0.56 m → {:.1} N/m, 0.66 m → {:.1} N/m",
        low.max_roof_force_up, high.max_roof_force_up
    );
    assert!(low.max_roof_force_up > high.max_roof_force_up);
}

/// Fig. 8–9 trade-off: a smaller time window (±8 steps) gives a peak roof pressure at least
/// as high as a larger one (±40 steps) on the same flow.
#[test]
fn smaller_window_gives_higher_peak_pressure() {
    let narrow = run_script(
        "paper_2d_roof.rhai",
        &["smoothing_steps=8"],
        &out_dir("roof_w8"),
    )
    .unwrap();
    let wide = run_script(
        "paper_2d_roof.rhai",
        &["smoothing_steps=40"],
        &out_dir("roof_w40"),
    )
    .unwrap();
    eprintln!(
        "peak roof pressure: ±8 steps {:.0} Pa, ±40 steps {:.0} Pa",
        narrow.max_roof_p, wide.max_roof_p
    );
    assert!(narrow.max_roof_p >= wide.max_roof_p);
}

/// Fig. 10 trend: at the same clearance H'/H = 0.2, the wider tank (1.0 m) carries a larger
/// peak roof force than the narrower one (0.5 m), each excited at its first mode. The paper
/// compares maxima over runs of up to 50 s, once both tanks hit the roof repeatedly; to keep
/// the run short the amplitude is the §3.2 one (0.0279 m), so both crests reach the roof
/// within ≈ 1.2 s and 4 s of excitation cover several impacts in each tank.
#[test]
fn wider_tank_carries_larger_roof_force() {
    let sets = |w: &str| {
        vec![
            format!("width={w}"),
            "duration=6".to_string(),
            "amplitude=0.0279".to_string(),
            "clearance_ratio=0.2".to_string(),
        ]
    };
    let run = |w: &str| {
        let s = sets(w);
        let s: Vec<&str> = s.iter().map(|x| x.as_str()).collect();
        run_script(
            "paper_2d_roof_sweep.rhai",
            &s,
            &out_dir(&format!("roof_width_{w}")),
        )
        .unwrap()
    };
    let narrow = run("0.5");
    let wide = run("1.0");
    eprintln!(
        "peak roof force at H'/H = 0.2: 0.5 m → {:.1} N/m, 1.0 m → {:.1} N/m",
        narrow.max_roof_force_up, wide.max_roof_force_up
    );
    assert!(narrow.max_roof_force_up > 0.0);
    assert!(wide.max_roof_force_up > narrow.max_roof_force_up);
}
