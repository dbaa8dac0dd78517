//! Links between the ships and the test article through the engine (docs/model.md §5.6): a look
//! starts when its last order arrives, a report arrives after its slowest receiver's delay, and
//! jitter stays within its bounds and repeats with the seed.

mod common;

use common::{config, run};
use mimo_core::ids::RadarId;
use mimo_core::records::{DwellKind, Requester};
use mimo_scenario::links::{Links, ShipLink};
use mimo_sim::World;
use mimo_sim::messages::{DwellFilter, DwellRequest, Reply, Request, StartInfo, Subscription, TaEvent, TxOrder};
use mimo_sim::test_article::{TaFault, TestArticle};

const R1: RadarId = RadarId(0);
const R2: RadarId = RadarId(1);
const R3: RadarId = RadarId(2);
const DURATION_S: f64 = 30.0;

fn world(links: Links) -> World {
    let mut s = mimo_scenario::load_standard(1).expect("scenario 1");
    s.duration_s = DURATION_S;
    s.links = links;
    World::new(s).expect("world")
}

/// Orders at t = 0 MIMO looks at airliner A for `earliest` times (R1 and R3 transmit, R2
/// receives too), and records (group start, group end, delivery time) of each report.
struct Orders<'w> {
    world: &'w World,
    earliest: Vec<f64>,
    seen: Vec<(f64, f64, f64)>,
}

impl TestArticle for Orders<'_> {
    fn name(&self) -> &str {
        "links-test"
    }
    fn subscription(&self) -> Subscription {
        Subscription { dwells: DwellFilter::All, primitives: false, batch: true }
    }
    fn on_start(&mut self, _start: &StartInfo) -> Result<Reply, TaFault> {
        let a = self.world.scenario.target_index("A").expect("airliner A");
        let reqs = self
            .earliest
            .iter()
            .map(|&t| {
                Request::Dwell(DwellRequest {
                    kind: DwellKind::Mimo,
                    earliest_s: t,
                    aim_ecef: self.world.targets_at(t.max(1.0))[a].pos_ecef,
                    transmitters: vec![TxOrder { radar: R1, n_pulses: 4 }, TxOrder { radar: R3, n_pulses: 4 }],
                    receivers: vec![R1, R2],
                    window_half_m: 1000.0,
                    predicted_snr: None,
                    tag: Vec::new(),
                })
            })
            .collect();
        Ok(Reply::requests(reqs))
    }
    fn on_dwell(&mut self, _r: &mimo_sim::messages::DwellReport) -> Result<Reply, TaFault> {
        Ok(Reply::default())
    }
    fn on_wake(&mut self, _t_s: f64) -> Result<Reply, TaFault> {
        Ok(Reply::default())
    }
    fn on_events(&mut self, t_s: f64, events: &[TaEvent]) -> Result<Reply, TaFault> {
        let mut reply = Reply::default();
        for e in events {
            match e {
                TaEvent::Start(s) => reply = self.on_start(s)?,
                TaEvent::DwellEnded(r) if r.requested_by == Requester::Ta => {
                    self.seen.push((r.t_s - 0.5 * r.duration_s, r.end_s, t_s));
                }
                _ => {}
            }
        }
        Ok(reply)
    }
}

fn looks(links: Links, earliest: &[f64], seed: u64) -> Vec<(f64, f64, f64)> {
    let w = world(links);
    let mut ta = Orders { world: &w, earliest: earliest.to_vec(), seen: Vec::new() };
    run(&w, &config(seed, DURATION_S), &mut ta);
    ta.seen
}

#[test]
fn a_look_starts_when_its_last_order_arrives_and_its_report_arrives_late() {
    // R1's orders take 0.2 s, R3's 1.5 s, R2's 0.7 s: a look ordered for t = 0 starts at 1.5 s;
    // its report goes out from R1 (0.2 s) and R2 (0.7 s), so it arrives 0.7 s after the end.
    let ships = [
        ("R1".to_string(), ShipLink { delay_s: 0.2, jitter_s: 0.0 }),
        ("R2".to_string(), ShipLink { delay_s: 0.7, jitter_s: 0.0 }),
        ("R3".to_string(), ShipLink { delay_s: 1.5, jitter_s: 0.0 }),
    ];
    let seen = looks(Links { ships: ships.into(), ..Links::default() }, &[0.0, 10.0], 3);
    assert_eq!(seen.len(), 2, "{seen:?}");
    let (start, end, delivered) = seen[0];
    // Not before its last order arrives; later only by a radar's background search dwell already
    // under way at 1.5 s (tens of milliseconds at most).
    assert!((1.5 - 1e-9..1.55).contains(&start), "{seen:?}");
    assert!((delivered - end - 0.7).abs() < 1e-9, "{seen:?}");
    // A look ordered for later than its orders take starts when asked.
    assert!((seen[1].0 - 10.0).abs() < 1e-9, "{seen:?}");
    // Perfect links: at once, delivered at the end.
    let seen = looks(Links::default(), &[0.0], 3);
    assert!(seen[0].0.abs() < 1e-9 && (seen[0].2 - seen[0].1).abs() < 1e-9, "{seen:?}");
}

#[test]
fn jitter_stays_within_its_bounds_and_repeats_with_the_seed() {
    let links = Links { delay_s: 1.0, jitter_s: 0.4, ..Links::default() };
    let earliest: Vec<f64> = (0..10).map(|i| f64::from(i) * 0.01).collect();
    let seen = looks(links.clone(), &earliest, 5);
    assert_eq!(seen.len(), earliest.len(), "{seen:?}");
    let mut lates = Vec::new();
    for &(start, end, delivered) in &seen {
        // The first look starts when its slowest order arrives: within [0.6, 1.4] s.
        assert!(start >= 0.6 - 1e-9, "{seen:?}");
        let late = delivered - end;
        assert!((0.6 - 1e-9..=1.4 + 1e-9).contains(&late), "{late}");
        lates.push(late);
    }
    assert!(seen[0].0 <= 1.4 + 1e-9, "{seen:?}");
    // Different messages are delayed differently; the same seed gives the same delays.
    assert!(lates.iter().any(|&l| (l - lates[0]).abs() > 1e-6), "{lates:?}");
    assert_eq!(looks(links, &earliest, 5), seen);
}
