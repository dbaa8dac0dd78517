//! Exact rectangular linear assignment.
//!
//! [`solve`] is the shortest-augmenting-path algorithm of Jonker & Volgenant in the form of
//! Crouse, "On implementing 2D rectangular assignment algorithms", IEEE TAES 52(4), 2016 (the one
//! behind scipy's `linear_sum_assignment` and TCL's `assign2D`). It runs in O(n²m) for an n×m
//! matrix. [`assign_with_miss`] adds a per-row "miss" option and forbidden (infinite) entries,
//! which is what gated GNN association and gated truth–track pairing need.

/// Minimum-cost assignment of every row of an `n_rows × n_cols` row-major matrix of **finite**
/// costs to a distinct column. Requires `n_rows <= n_cols`. Returns the column of each row.
pub fn solve(cost: &[f64], n_rows: usize, n_cols: usize) -> Vec<usize> {
    assert!(n_rows <= n_cols, "assignment needs rows <= cols");
    assert_eq!(cost.len(), n_rows * n_cols);
    let mut s = Solver::new(n_rows, n_cols);
    for cur_row in 0..n_rows {
        let (sink, min_val) = s.shortest_path(cost, cur_row);
        s.augment(cur_row, sink, min_val);
    }
    s.col4row
}

/// The duals, the assignment so far and the work arrays of [`solve`].
struct Solver {
    n: usize,
    m: usize,
    u: Vec<f64>,
    v: Vec<f64>,
    col4row: Vec<usize>,
    row4col: Vec<usize>,
    shortest: Vec<f64>,
    path: Vec<usize>,
    sr: Vec<bool>,
    sc: Vec<bool>,
    remaining: Vec<usize>,
}

impl Solver {
    fn new(n: usize, m: usize) -> Solver {
        Solver {
            n,
            m,
            u: vec![0.0; n],
            v: vec![0.0; m],
            col4row: vec![usize::MAX; n],
            row4col: vec![usize::MAX; m],
            shortest: vec![0.0; m],
            path: vec![usize::MAX; m],
            sr: vec![false; n],
            sc: vec![false; m],
            remaining: Vec::with_capacity(m),
        }
    }

    /// Dijkstra-like search for the shortest augmenting path from `cur_row`. Returns the
    /// unassigned column it ends at and its reduced length.
    fn shortest_path(&mut self, cost: &[f64], cur_row: usize) -> (usize, f64) {
        let m = self.m;
        let (u, v, row4col) = (&self.u, &self.v, &self.row4col);
        let (shortest, path, sr, sc, remaining) =
            (&mut self.shortest, &mut self.path, &mut self.sr, &mut self.sc, &mut self.remaining);
        shortest.iter_mut().for_each(|x| *x = f64::INFINITY);
        path.iter_mut().for_each(|x| *x = usize::MAX);
        sr.iter_mut().for_each(|x| *x = false);
        sc.iter_mut().for_each(|x| *x = false);
        remaining.clear();
        remaining.extend((0..m).rev());
        let mut min_val = 0.0;
        let mut i = cur_row;
        loop {
            sr[i] = true;
            let mut index = usize::MAX;
            let mut lowest = f64::INFINITY;
            for (it, &j) in remaining.iter().enumerate() {
                let r = min_val + cost[i * m + j] - u[i] - v[j];
                if r < shortest[j] {
                    path[j] = i;
                    shortest[j] = r;
                }
                // Prefer an unassigned column on ties, as in Crouse's implementation.
                if shortest[j] < lowest || (shortest[j] == lowest && row4col[j] == usize::MAX) {
                    lowest = shortest[j];
                    index = it;
                }
            }
            min_val = lowest;
            if index == usize::MAX || !min_val.is_finite() {
                // Infeasible (only possible with non-finite costs).
                panic!("assignment infeasible: costs must be finite");
            }
            let j = remaining.swap_remove(index);
            sc[j] = true;
            if row4col[j] == usize::MAX {
                return (j, min_val);
            }
            i = row4col[j];
        }
    }

    /// Update the duals after a search from `cur_row` that ended at column `sink` with reduced
    /// length `min_val`, and augment the assignment along its path.
    fn augment(&mut self, cur_row: usize, sink: usize, min_val: f64) {
        self.u[cur_row] += min_val;
        for r in 0..self.n {
            if self.sr[r] && r != cur_row {
                self.u[r] += min_val - self.shortest[self.col4row[r]];
            }
        }
        for c in 0..self.m {
            if self.sc[c] {
                self.v[c] -= min_val - self.shortest[c];
            }
        }
        let mut j = sink;
        loop {
            let r = self.path[j];
            self.row4col[j] = r;
            let prev = self.col4row[r];
            self.col4row[r] = j;
            if r == cur_row {
                break;
            }
            j = prev;
        }
    }
}

/// Gated assignment with a per-row miss cost. `cost` is `n_rows × n_cols` row-major; entries
/// that are not finite are forbidden. Every row is either given a distinct column or left
/// unassigned at cost `miss_cost[row]` (finite). Returns the column of each row, or `None`.
/// Columns may be left unassigned at no cost.
pub fn assign_with_miss(cost: &[f64], n_rows: usize, n_cols: usize, miss_cost: &[f64]) -> Vec<Option<usize>> {
    assert_eq!(cost.len(), n_rows * n_cols);
    assert_eq!(miss_cost.len(), n_rows);
    if n_rows == 0 {
        return Vec::new();
    }
    // Shift so that every cost is >= 0, then a forbidden value above any feasible total.
    let finite = cost.iter().chain(miss_cost).copied().filter(|c| c.is_finite());
    let min_c = finite.clone().fold(0.0f64, f64::min);
    let total: f64 = finite.map(|c| c - min_c).sum();
    let forbidden = 2.0 * total + 1.0;
    let w = n_cols + n_rows;
    let mut big = vec![forbidden; n_rows * w];
    for r in 0..n_rows {
        for c in 0..n_cols {
            let x = cost[r * n_cols + c];
            if x.is_finite() {
                big[r * w + c] = x - min_c;
            }
        }
        big[r * w + n_cols + r] = miss_cost[r] - min_c;
    }
    let sol = solve(&big, n_rows, w);
    sol.iter()
        .enumerate()
        .map(|(r, &c)| if c < n_cols && cost[r * n_cols + c].is_finite() { Some(c) } else { None })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Stream;

    fn brute(cost: &[f64], n: usize, m: usize, miss: &[f64]) -> f64 {
        fn rec(r: usize, used: &mut Vec<bool>, cost: &[f64], n: usize, m: usize, miss: &[f64]) -> f64 {
            if r == n {
                return 0.0;
            }
            let mut best = miss[r] + rec(r + 1, used, cost, n, m, miss);
            for c in 0..m {
                let x = cost[r * m + c];
                if !used[c] && x.is_finite() {
                    used[c] = true;
                    best = best.min(x + rec(r + 1, used, cost, n, m, miss));
                    used[c] = false;
                }
            }
            best
        }
        rec(0, &mut vec![false; m], cost, n, m, miss)
    }

    #[test]
    fn square_known_answer() {
        // Classic 3×3 example: optimum is 0→1, 1→0, 2→2 with cost 5.
        let c = [4.0, 1.0, 3.0, 2.0, 0.0, 5.0, 3.0, 2.0, 2.0];
        let s = solve(&c, 3, 3);
        assert_eq!(s, vec![1, 0, 2]);
    }

    #[test]
    fn matches_brute_force_on_random_gated_problems() {
        let mut rng = Stream::new(11, &[crate::rng::domain::TEST]);
        for trial in 0..300 {
            let n = 1 + (trial % 5);
            let m = 1 + ((trial / 5) % 6);
            let cost: Vec<f64> = (0..n * m)
                .map(|_| if rng.uniform() < 0.3 { f64::INFINITY } else { (rng.uniform() * 10.0).round() - 2.0 })
                .collect();
            let miss: Vec<f64> = (0..n).map(|_| rng.uniform() * 8.0).collect();
            let sol = assign_with_miss(&cost, n, m, &miss);
            let mut used = vec![false; m];
            let mut total = 0.0;
            for (r, c) in sol.iter().enumerate() {
                match c {
                    Some(c) => {
                        assert!(!used[*c]);
                        used[*c] = true;
                        total += cost[r * m + c];
                    }
                    None => total += miss[r],
                }
            }
            let best = brute(&cost, n, m, &miss);
            assert!((total - best).abs() < 1e-9, "trial {trial}: {total} vs {best}");
        }
    }
}
