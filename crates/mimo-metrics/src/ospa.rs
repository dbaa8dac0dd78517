//! OSPA and GOSPA distances between a set of truths and a set of tracks.
//!
//! * OSPA (Schuhmacher, Vo & Vo, IEEE TSP 56(8), 2008), for |X| = n ≤ |Y| = m:
//!   `OSPA = ( (1/m) · ( min_π Σ_i d_c(x_i, y_π(i))^p + c^p·(m − n) ) )^(1/p)`, with
//!   `d_c = min(d, c)`.
//! * GOSPA with α = 2 (García-Fernández, Rahmathullah & Svensson, IEEE TSP 65(24), 2017, Prop. 1):
//!   `GOSPA = ( min_π Σ_i d_c(x_i, y_π(i))^p + (c^p / 2)·(m − n) )^(1/p)`. Unlike OSPA it is not
//!   normalized by the cardinality, so it grows with the number of targets; it splits into
//!   localisation error, `c^p/2` per missed truth and `c^p/2` per false track.
//!
//! Both use the same optimal assignment (of the smaller set into the larger one on the cost
//! `d_c^p`), solved exactly with [`mimo_core::assign::solve`], one component of the pairs closer
//! than `c` at a time ([`mimo_core::assign_components::solve_below_cut`]): every other pairing
//! costs `c^p` whichever it is. Both are 0 for two empty sets; the metrics engine reports null at
//! such times instead (see the crate docs).

use glam::DVec3;
use mimo_core::assign_components::solve_below_cut;

/// OSPA and GOSPA of one pair of sets.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OspaGospa {
    /// OSPA distance (m).
    pub ospa_m: f64,
    /// GOSPA distance with α = 2 (m).
    pub gospa_m: f64,
    /// GOSPA's localisation part: `(Σ d^p)^(1/p)` over the pairs closer than `c` (m).
    pub gospa_localisation_m: f64,
    /// GOSPA's missed truths: truths left unpaired or paired at `c` or farther.
    pub gospa_missed: u32,
    /// GOSPA's false tracks: tracks left unpaired or paired at `c` or farther.
    pub gospa_false: u32,
}

/// OSPA and GOSPA (α = 2) between truths `x` and tracks `y` with cut-off `c_m` (m) and order `p`.
pub fn ospa_gospa(x: &[DVec3], y: &[DVec3], c_m: f64, p: f64) -> OspaGospa {
    let (a, b) = if x.len() <= y.len() { (x, y) } else { (y, x) };
    let (n, m) = (a.len(), b.len());
    if m == 0 {
        return OspaGospa { ospa_m: 0.0, gospa_m: 0.0, gospa_localisation_m: 0.0, gospa_missed: 0, gospa_false: 0 };
    }
    let cp = c_m.powf(p);
    let mut cost = vec![0.0; n * m];
    for (i, ai) in a.iter().enumerate() {
        for (j, bj) in b.iter().enumerate() {
            // `min(d, c)^p`: a pair at the cut-off or beyond (or NaN, which `min` takes as
            // absent) costs `c^p`, computed once; in a raid most pairs are.
            let d = ai.distance(*bj);
            cost[i * m + j] = if d < c_m { crate::ospa_power::cost_power(d, p) } else { cp };
        }
    }
    let pairs: Vec<f64> = if n == 0 {
        Vec::new()
    } else {
        solve_below_cut(&cost, n, m, cp).iter().enumerate().map(|(i, j)| j.map_or(cp, |j| cost[i * m + j])).collect()
    };
    let loc: f64 = pairs.iter().sum();
    // A pair at the cut-off costs c^p = c^p/2 (a miss) + c^p/2 (a false track): GOSPA's split.
    let cut = pairs.iter().filter(|&&d| d >= cp).count() as u32;
    let inside: f64 = pairs.iter().filter(|&&d| d < cp).sum();
    let unmatched = (m - n) as f64;
    let (missed, false_) = if x.len() <= y.len() { (cut, cut + (m - n) as u32) } else { (cut + (m - n) as u32, cut) };
    OspaGospa {
        ospa_m: ((loc + cp * unmatched) / m as f64).powf(1.0 / p),
        gospa_m: (loc + 0.5 * cp * unmatched).powf(1.0 / p),
        gospa_localisation_m: inside.powf(1.0 / p),
        gospa_missed: missed,
        gospa_false: false_,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mimo_core::assign::solve;

    /// The cost of every pair is bit for bit `min(d, c)^p` (the definition), whether the pair is
    /// inside the cut-off, at it or beyond: the figures equal those of the plain formula on the
    /// whole matrix, for a small scene (solved whole) and a large one (solved by component).
    #[test]
    fn far_pairs_cost_exactly_the_cut_off() {
        let mut rng = 12345u64;
        let mut next = || {
            rng = rng.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (rng >> 11) as f64 / (1u64 << 53) as f64
        };
        for (p, (nx, ny, side_m)) in
            [1.0, 2.0, 1.7].into_iter().flat_map(|p| [(p, (7, 9, 300.0)), (p, (60, 70, 900.0))])
        {
            let x: Vec<DVec3> = (0..nx).map(|_| DVec3::new(next(), next(), next()) * side_m).collect();
            let mut y: Vec<DVec3> = (0..ny).map(|_| DVec3::new(next(), next(), next()) * side_m).collect();
            y.push(x[0] + DVec3::new(100.0, 0.0, 0.0)); // exactly at the cut-off
            let c = 100.0;
            let got = ospa_gospa(&x, &y, c, p);
            let (a, b) = (&x[..], &y[..]);
            let m = b.len();
            let pairs = solve(
                &a.iter().flat_map(|ai| b.iter().map(|bj| ai.distance(*bj).min(c).powf(p))).collect::<Vec<_>>(),
                a.len(),
                m,
            );
            let loc: f64 = pairs.iter().enumerate().map(|(i, &j)| a[i].distance(b[j]).min(c).powf(p)).sum();
            let want = ((loc + c.powf(p) * (m - a.len()) as f64) / m as f64).powf(1.0 / p);
            assert_eq!(got.ospa_m.to_bits(), want.to_bits(), "p = {p}");
        }
    }

    #[test]
    fn hand_cases() {
        let c = 100.0;
        let truths = [DVec3::ZERO, DVec3::new(10_000.0, 0.0, 0.0)];
        // One track 30 m from the first truth, one far from everything.
        let tracks = [DVec3::new(0.0, 30.0, 0.0), DVec3::new(0.0, 0.0, 50_000.0)];
        let r = ospa_gospa(&truths, &tracks, c, 2.0);
        assert!((r.ospa_m - (5450.0f64).sqrt()).abs() < 1e-9, "{r:?}");
        assert!((r.gospa_m - (10_900.0f64).sqrt()).abs() < 1e-9, "{r:?}");
        // Its parts: 30 m of localisation, the far truth missed, the far track false; and
        // GOSPA^p = localisation^p + c^p/2 · (missed + false).
        assert!((r.gospa_localisation_m - 30.0).abs() < 1e-9 && (r.gospa_missed, r.gospa_false) == (1, 1), "{r:?}");
        let parts = r.gospa_localisation_m.powi(2) + 0.5 * c * c * f64::from(r.gospa_missed + r.gospa_false);
        assert!((parts - r.gospa_m.powi(2)).abs() < 1e-6);
        // A third track, also far: m − n = 1.
        let tracks3 = [tracks[0], tracks[1], DVec3::new(0.0, -50_000.0, 0.0)];
        let r = ospa_gospa(&truths, &tracks3, c, 2.0);
        assert!((r.ospa_m - (20_900.0f64 / 3.0).sqrt()).abs() < 1e-9, "{r:?}");
        assert!((r.gospa_m - (15_900.0f64).sqrt()).abs() < 1e-9, "{r:?}");
        assert_eq!((r.gospa_missed, r.gospa_false), (1, 2));
        // Symmetric in its arguments.
        let s = ospa_gospa(&tracks3, &truths, c, 2.0);
        assert!((s.ospa_m - r.ospa_m).abs() < 1e-12 && (s.gospa_m - r.gospa_m).abs() < 1e-12);
        assert_eq!((s.gospa_missed, s.gospa_false), (2, 1), "misses and false tracks swap with the arguments");
        // Empty cases.
        let zero = ospa_gospa(&[], &[], c, 2.0);
        assert_eq!((zero.ospa_m, zero.gospa_m, zero.gospa_missed, zero.gospa_false), (0.0, 0.0, 0, 0));
        let e = ospa_gospa(&truths, &[], c, 2.0);
        assert_eq!((e.gospa_missed, e.gospa_false), (2, 0));
        assert!((e.ospa_m - c).abs() < 1e-12);
        assert!((e.gospa_m - (c * c).sqrt()).abs() < 1e-9); // (2 · c²/2)^(1/2) = c
        // p = 1: plain sums.
        let r1 = ospa_gospa(&truths[..1], &tracks[..1], c, 1.0);
        assert!((r1.ospa_m - 30.0).abs() < 1e-12 && (r1.gospa_m - 30.0).abs() < 1e-12);
    }
}
