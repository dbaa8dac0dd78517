//! Registration biases end to end through the engine (docs/model.md §5.5): measurements carry
//! the biases set for their radars, the reported covariances do not, truth does not, and the
//! run's biases are its `biases` rows.

mod common;

use common::{config, run};
use mimo_core::DVec3;
use mimo_core::ids::RadarId;
use mimo_core::records::{DwellKind, MeasurementRow, RunTables};
use mimo_core::registration::RadarBias;
use mimo_radar::registration::{reported_direction, up_in_face};
use mimo_sim::World;
use mimo_sim::messages::{DwellReport, DwellRequest, Reply, Request, StartInfo, TxOrder};
use mimo_sim::test_article::{TaFault, TestArticle};
use std::collections::BTreeMap;

const R1: RadarId = RadarId(0);
const R2: RadarId = RadarId(1);
const R3: RadarId = RadarId(2);
const R4: RadarId = RadarId(3);
const DURATION_S: f64 = 150.0;

/// Scenario 1 cut to [`DURATION_S`] with `set` biases.
fn world(set: &[(RadarId, RadarBias)]) -> World {
    let mut s = mimo_scenario::load_standard(1).expect("scenario 1");
    s.duration_s = DURATION_S;
    s.biases.radars = set.iter().map(|(r, b)| (r.to_string(), *b)).collect();
    World::new(s).expect("world")
}

/// MIMO dwells every second at airliner A (from truth: a test may): R1 and R3 transmit, R1, R2
/// and R4 receive, so every channel kind is there (monostatic, bistatic, receive only).
struct Cued<'w> {
    world: &'w World,
}

impl TestArticle for Cued<'_> {
    fn name(&self) -> &str {
        "cued-registration-test"
    }
    fn on_start(&mut self, _start: &StartInfo) -> Result<Reply, TaFault> {
        let a = self.world.scenario.target_index("A").expect("airliner A");
        let reqs = (1..DURATION_S as u32 - 1)
            .map(|i| {
                let t = f64::from(i);
                Request::Dwell(DwellRequest {
                    kind: DwellKind::Mimo,
                    earliest_s: t,
                    aim_ecef: self.world.targets_at(t)[a].pos_ecef,
                    transmitters: vec![TxOrder { radar: R1, n_pulses: 8 }, TxOrder { radar: R3, n_pulses: 8 }],
                    receivers: vec![R1, R2, R4],
                    window_half_m: 1000.0,
                    predicted_snr: None,
                    tag: Vec::new(),
                })
            })
            .collect();
        Ok(Reply::requests(reqs))
    }
    fn on_dwell(&mut self, _report: &DwellReport) -> Result<Reply, TaFault> {
        Ok(Reply::default())
    }
    fn on_wake(&mut self, _t_s: f64) -> Result<Reply, TaFault> {
        Ok(Reply::default())
    }
}

fn simulate(world: &World) -> RunTables {
    run(world, &config(11, DURATION_S), &mut Cued { world }).0
}

/// Airliner A's true (ρ, u, v) in measurement `m`'s channel, and its receiving face's vertical.
fn truth_of(world: &World, m: &MeasurementRow) -> (f64, f64, f64, DVec3) {
    let a = world.scenario.target_index("A").expect("A");
    let p = world.targets_at(m.t_s)[a].pos_ecef;
    let face = world.face_at(m.rx, m.rx_face, m.t_s).expect("face");
    let s = face.to_sine(p);
    let rho = 0.5 * ((p - world.site_at(m.tx, m.t_s)).length() + s.range_m);
    (rho, s.u, s.v, up_in_face(&face))
}

/// Airliner A's unmerged measurements from the ordered MIMO looks (the radars' own background
/// search sees A too, at low SNR and off its beam centre, which these tests are not about).
fn of_a(t: &RunTables) -> impl Iterator<Item = &MeasurementRow> {
    let mimo: std::collections::BTreeSet<u64> =
        t.dwells.iter().filter(|d| d.kind == DwellKind::Mimo).map(|d| d.dwell_id).collect();
    t.measurements
        .iter()
        .filter(move |m| m.target_hint.as_deref() == Some("A") && !m.merged && mimo.contains(&m.dwell_id))
}

#[test]
fn range_biases_shift_every_range_by_half_its_two_radars_and_nothing_else() {
    let set = [
        (R1, RadarBias { range_m: 40.0, ..RadarBias::default() }),
        (R2, RadarBias { range_m: 10.0, ..RadarBias::default() }),
        (R3, RadarBias { range_m: -20.0, ..RadarBias::default() }),
    ];
    let (plain, biased) = (simulate(&world(&[])), simulate(&world(&set)));
    let bias = |r: RadarId| set.iter().find(|(x, _)| *x == r).map_or(0.0, |(_, b)| b.range_m);
    assert!(plain.measurements.len() > 500, "{} measurements", plain.measurements.len());
    assert_eq!(plain.measurements.len(), biased.measurements.len());
    let mut channels = BTreeMap::new();
    for (p, b) in plain.measurements.iter().zip(&biased.measurements) {
        let want = 0.5 * (bias(p.tx) + bias(p.rx));
        assert!((b.range_m - p.range_m - want).abs() < 1e-6, "{} vs {} + {want}", b.range_m, p.range_m);
        // The reported covariance and everything else are those of the unbiased radar.
        let mut unshifted = b.clone();
        unshifted.range_m = p.range_m;
        assert_eq!(&unshifted, p);
        *channels.entry((p.tx, p.rx)).or_insert(0) += 1;
    }
    // Monostatic and bistatic channels were both there.
    assert!(channels.contains_key(&(R1, R1)) && channels.contains_key(&(R3, R2)), "{channels:?}");
    // Truth is unbiased, and the biases are the run's `biases` rows.
    assert_eq!(plain.truth, biased.truth);
    assert!(plain.biases.is_empty());
    let rows: Vec<(RadarId, f64)> = biased.biases.iter().map(|r| (r.radar, r.range_m)).collect();
    assert_eq!(rows, vec![(R1, 40.0), (R2, 10.0), (R3, -20.0), (R4, 0.0)]);
}

#[test]
fn measurement_errors_carry_the_set_biases() {
    let set = [
        (R1, RadarBias { range_m: 25.0, u: -2e-3, ..RadarBias::default() }),
        (R2, RadarBias { u: 4e-3, v: -3e-3, heading_deg: 0.2, ..RadarBias::default() }),
        (R4, RadarBias { heading_deg: -0.3, ..RadarBias::default() }),
    ];
    let w = world(&set);
    let t = simulate(&w);
    let bias = |r: RadarId| set.iter().find(|(x, _)| *x == r).map_or(RadarBias::default(), |(_, b)| *b);
    // Per receiver: sums of the error left once the expected bias is removed, of its square over
    // the reported variance, of the raw error's, and of the expected bias itself.
    #[derive(Default, Debug)]
    struct Sums {
        n: f64,
        left: [f64; 3],
        nees_left: f64,
        nees_raw: f64,
        shift: [f64; 3],
        var: [f64; 3],
    }
    let mut by_rx: BTreeMap<RadarId, Sums> = BTreeMap::new();
    for m in of_a(&t) {
        let (rho, u, v, up) = truth_of(&w, m);
        let (bt, br) = (bias(m.tx), bias(m.rx));
        let (ub, vb) = reported_direction(u, v, up, &br).expect("in front");
        let want = [rho + 0.5 * (bt.range_m + br.range_m), ub, vb];
        let truth = [rho, u, v];
        let got = [m.range_m, m.u, m.v];
        let var = [m.var_range_m2, m.var_u, m.var_v];
        let s = by_rx.entry(m.rx).or_default();
        s.n += 1.0;
        for k in 0..3 {
            s.left[k] += got[k] - want[k];
            s.shift[k] += want[k] - truth[k];
            s.var[k] += var[k];
            s.nees_left += (got[k] - want[k]).powi(2) / var[k];
            s.nees_raw += (got[k] - truth[k]).powi(2) / var[k];
        }
    }
    for (rx, s) in &by_rx {
        assert!(s.n > 100.0, "{rx}: {s:?}");
        for k in 0..3 {
            // The mean error is the set bias: what is left is within 5σ of its mean over n.
            let band = 5.0 * (s.var[k] / s.n / s.n).sqrt();
            assert!((s.left[k] / s.n).abs() < band, "{rx} component {k}: left {} band {band}", s.left[k] / s.n);
        }
        // Without the bias the errors match the reported covariance (χ²₃ per measurement, mean 3;
        // loose band: the model's own NEES is within [2.5, 3.6], docs/model.md §4.8).
        let nees = s.nees_left / s.n;
        assert!((2.0..4.5).contains(&nees), "{rx}: NEES without the bias {nees}");
    }
    // The angle biases of R2 (4 and −3 mrad, and 0.2° of heading, which turns u against its own
    // bias here) move its directions by more than its noise: the covariance does not hold them.
    let r2 = &by_rx[&R2];
    assert!(r2.shift[1].hypot(r2.shift[2]) / r2.n > 2e-3, "{r2:?}");
    assert!(r2.nees_raw / r2.n > 2.0 * r2.nees_left / r2.n, "{r2:?}");
    // R4's heading bias alone moves its directions (and, above, its bistatic measurements of R1's
    // pulses carry R4's angle biases, not R1's).
    assert!(by_rx[&R4].shift[1].abs() / by_rx[&R4].n > 1e-3, "{:?}", by_rx[&R4]);
}

/// Reports `rows` as its registration estimate when the run finishes.
struct Reports(Vec<mimo_core::records::RegistrationRow>);

impl TestArticle for Reports {
    fn name(&self) -> &str {
        "registration-report-test"
    }
    fn on_start(&mut self, _start: &StartInfo) -> Result<Reply, TaFault> {
        Ok(Reply::default())
    }
    fn on_dwell(&mut self, _report: &DwellReport) -> Result<Reply, TaFault> {
        Ok(Reply::default())
    }
    fn on_wake(&mut self, _t_s: f64) -> Result<Reply, TaFault> {
        Ok(Reply::default())
    }
    fn on_finish(&mut self, _t_s: f64) -> Result<Reply, TaFault> {
        Ok(Reply { registration: std::mem::take(&mut self.0), ..Reply::default() })
    }
}

fn estimate_row(radar: RadarId) -> mimo_core::records::RegistrationRow {
    mimo_core::records::RegistrationRow {
        run: 99,
        t_s: 20.0,
        radar,
        range_m: 1.5,
        u: 0.0,
        v: 0.0,
        heading_deg: 0.0,
        var_range_m2: 4.0,
        var_u: 1e-6,
        var_v: 1e-6,
        var_heading_deg2: 1e-2,
        cov_range_u_m: 0.0,
        cov_range_v_m: 0.0,
        cov_range_heading_m_deg: 0.0,
        cov_u_v: 0.0,
        cov_u_heading_deg: 0.0,
        cov_v_heading_deg: 0.0,
        looks: 3,
    }
}

#[test]
fn registration_estimates_reach_the_table_stamped_and_bad_ones_are_the_test_articles_fault() {
    let mut s = mimo_scenario::load_standard(1).expect("scenario 1");
    s.duration_s = 20.0;
    let w = World::new(s).expect("world");
    let cfg = config(3, 20.0);
    let mut tables = RunTables::default();
    let mut ta = Reports(vec![estimate_row(R2)]);
    mimo_sim::run_one(&w, &cfg, 4, &mut ta, &mut tables).expect("run");
    assert_eq!(tables.registration, vec![mimo_core::records::RegistrationRow { run: 4, ..estimate_row(R2) }]);
    // An unknown radar, a number that is not finite, a variance that is not positive.
    let bad = [
        (mimo_core::records::RegistrationRow { radar: RadarId(7), ..estimate_row(R1) }, "unknown radar R8"),
        (mimo_core::records::RegistrationRow { u: f64::NAN, ..estimate_row(R1) }, "not finite"),
        (mimo_core::records::RegistrationRow { var_v: 0.0, ..estimate_row(R1) }, "not positive"),
    ];
    for (row, why) in bad {
        let mut tables = RunTables::default();
        let e = mimo_sim::run_one(&w, &cfg, 0, &mut Reports(vec![row]), &mut tables).expect_err(why);
        assert!(e.to_string().contains(why), "{e}");
        assert!(tables.registration.is_empty());
    }
}
