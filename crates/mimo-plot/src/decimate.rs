//! Thinning of sampled paths (truth and track polylines) within a stated position tolerance.
//!
//! The page draws a path as chords between its kept samples and places an object at time t by
//! linear interpolation along them, so the error that matters is the *time-synchronised*
//! distance: a sample at time tᵢ against the point of the chord of its kept neighbours at tᵢ.
//! [`keep_within`] is Douglas–Peucker with that distance: every dropped sample is within the
//! tolerance of the thinned path at its own time (so also within it of the drawn polyline),
//! and the first and last samples are always kept.

/// Time-synchronised distance (m) of sample `i` from the chord of samples `a` and `b`.
fn sed_m(t: &[f64], p: &[[f64; 3]], a: usize, b: usize, i: usize) -> f64 {
    let dt = t[b] - t[a];
    let w = if dt > 0.0 { (t[i] - t[a]) / dt } else { 0.0 };
    let (pa, pb, pi) = (p[a], p[b], p[i]);
    (0..3).map(|k| (pi[k] - (pa[k] + w * (pb[k] - pa[k]))).powi(2)).sum::<f64>().sqrt()
}

/// Which samples of a path (times `t_s`, non-decreasing, and positions `p_m`) to keep so that
/// every dropped sample lies within `tol_m` of the linear interpolation of the kept ones at its
/// time. The first and last samples are kept; a tolerance ≤ 0 keeps every sample.
pub fn keep_within(t_s: &[f64], p_m: &[[f64; 3]], tol_m: f64) -> Vec<bool> {
    let n = t_s.len().min(p_m.len());
    if tol_m <= 0.0 || n <= 2 {
        return vec![true; n];
    }
    let mut keep = vec![false; n];
    keep[0] = true;
    keep[n - 1] = true;
    // Iterative, so a long path cannot exhaust the stack.
    let mut stack = vec![(0usize, n - 1)];
    while let Some((a, b)) = stack.pop() {
        if b <= a + 1 {
            continue;
        }
        let (mut worst, mut at) = (-1.0, a);
        for i in a + 1..b {
            let d = sed_m(t_s, p_m, a, b, i);
            if d > worst {
                (worst, at) = (d, i);
            }
        }
        if worst > tol_m {
            keep[at] = true;
            stack.push((a, at));
            stack.push((at, b));
        }
    }
    keep
}

/// Positions of flattened whole-metre triples as `f64` points.
pub fn points(flat: &[i64]) -> Vec<[f64; 3]> {
    flat.chunks_exact(3).map(|c| [c[0] as f64, c[1] as f64, c[2] as f64]).collect()
}

/// The position of a path at `t` by linear interpolation of its samples (clamped to its ends).
pub fn interp(t_s: &[f64], p_m: &[[f64; 3]], t: f64) -> Option<[f64; 3]> {
    let n = t_s.len().min(p_m.len());
    if n == 0 {
        return None;
    }
    let j = t_s[..n].partition_point(|&x| x <= t);
    if j == 0 {
        return Some(p_m[0]);
    }
    if j >= n {
        return Some(p_m[n - 1]);
    }
    let (a, b) = (j - 1, j);
    let dt = t_s[b] - t_s[a];
    let w = if dt > 0.0 { (t - t_s[a]) / dt } else { 0.0 };
    Some([0, 1, 2].map(|k| p_m[a][k] + w * (p_m[b][k] - p_m[a][k])))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A turning, accelerating, climbing path with some jitter, sampled at 10 Hz.
    fn path() -> (Vec<f64>, Vec<[f64; 3]>) {
        let t: Vec<f64> = (0..3000).map(|i| i as f64 * 0.1).collect();
        let p = t
            .iter()
            .enumerate()
            .map(|(i, &t)| {
                let jitter = ((i * 7919) % 13) as f64 - 6.0;
                let turn = if t > 100.0 { (t - 100.0).min(60.0) * 0.02 } else { 0.0 };
                let s = 250.0 * t + 0.5 * t * t * 0.1;
                [s * turn.cos() + jitter, s * turn.sin(), 8000.0 + 3.0 * t + jitter * 0.5]
            })
            .collect();
        (t, p)
    }

    #[test]
    fn every_sample_is_within_the_tolerance_of_the_thinned_path_and_the_ends_are_kept() {
        let (t, p) = path();
        for tol in [5.0, 20.0, 100.0] {
            let keep = keep_within(&t, &p, tol);
            assert!(keep[0] && keep[t.len() - 1]);
            let kt: Vec<f64> = t.iter().zip(&keep).filter(|x| *x.1).map(|x| *x.0).collect();
            let kp: Vec<[f64; 3]> = p.iter().zip(&keep).filter(|x| *x.1).map(|x| *x.0).collect();
            assert!(kt.len() < t.len() / 3, "tolerance {tol} m kept {} of {}", kt.len(), t.len());
            for (ti, pi) in t.iter().zip(&p) {
                let q = interp(&kt, &kp, *ti).expect("a point");
                let d = (0..3).map(|k| (pi[k] - q[k]).powi(2)).sum::<f64>().sqrt();
                assert!(d <= tol + 1e-9, "sample at {ti} s is {d} m off the thinned path (tolerance {tol} m)");
            }
        }
    }

    #[test]
    fn a_straight_constant_speed_path_keeps_its_two_ends_and_no_tolerance_keeps_all() {
        let t: Vec<f64> = (0..100).map(f64::from).collect();
        let p: Vec<[f64; 3]> = t.iter().map(|&t| [100.0 * t, -50.0 * t, 2.0 * t]).collect();
        let keep = keep_within(&t, &p, 1.0);
        assert_eq!(keep.iter().filter(|k| **k).count(), 2);
        assert!(keep[0] && keep[99]);
        assert!(keep_within(&t, &p, 0.0).iter().all(|k| *k));
        // A stop in the middle of a straight line is a timing change: it is kept.
        let p2: Vec<[f64; 3]> = (0..100)
            .map(|i| {
                p[if i <= 50 {
                    i
                } else if i <= 60 {
                    50
                } else {
                    i - 10
                }]
            })
            .collect();
        let keep2 = keep_within(&t, &p2, 1.0);
        assert!(keep2.iter().filter(|k| **k).count() >= 4);
        assert_eq!(keep_within(&[], &[], 1.0), Vec::<bool>::new());
        assert_eq!(keep_within(&[1.0], &[[0.0; 3]], 1.0), vec![true]);
    }
}
