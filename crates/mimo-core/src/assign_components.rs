//! An assignment problem split into the connected components of its bipartite graph.
//!
//! Rows and columns are the graph's two sides; an entry that may pair them (finite under a gate,
//! closer than a cut-off) is an edge. Pairs only form along edges, so every component is a
//! problem of its own: the optimum of the whole is the union of the components' optima, and
//! its total the sum of theirs. Solving each component with the exact solver of
//! [`crate::assign`] costs O(Σ nₖ²mₖ) in place of O(n²m), which is what keeps a score of
//! hundreds of targets spread over a region (a raid, docs/model.md §8.4) near linear in their
//! number. Where the optimum is unique, the assignment equals the one [`crate::assign`] finds on
//! the whole matrix; where several are optimal (exact ties in cost), either may be returned, with
//! the same total.
//!
//! A problem of at most [`WHOLE_UP_TO_ROWS`] rows is solved whole, exactly as before the split
//! existed: finding the components costs more than it saves there (about 2 % of a scenario-7
//! score's instructions), and every standard scenario stays on the solver it was scored with.

use crate::assign::{assign_with_miss, solve};

/// The most rows a problem may have to be solved whole rather than split.
pub const WHOLE_UP_TO_ROWS: usize = 32;

/// The components of the bipartite graph of `n_rows` rows and `n_cols` columns whose edges are
/// the entries with `edge(row, col)` true, each as its rows and its columns (ascending), in the
/// order of their first row. Rows and columns without an edge belong to no component.
pub fn components(n_rows: usize, n_cols: usize, edge: impl Fn(usize, usize) -> bool) -> Vec<(Vec<usize>, Vec<usize>)> {
    // Union–find over rows (0..n_rows) and columns (n_rows..n_rows + n_cols).
    let mut parent: Vec<usize> = (0..n_rows + n_cols).collect();
    fn root(parent: &mut [usize], mut x: usize) -> usize {
        while parent[x] != x {
            parent[x] = parent[parent[x]];
            x = parent[x];
        }
        x
    }
    let mut linked = vec![false; n_rows + n_cols];
    for r in 0..n_rows {
        for c in 0..n_cols {
            if edge(r, c) {
                linked[r] = true;
                linked[n_rows + c] = true;
                let (a, b) = (root(&mut parent, r), root(&mut parent, n_rows + c));
                if a != b {
                    // The smaller index is the root, so a component's root is its first row.
                    parent[a.max(b)] = a.min(b);
                }
            }
        }
    }
    let mut slot = vec![usize::MAX; n_rows + n_cols];
    let mut parts: Vec<(Vec<usize>, Vec<usize>)> = Vec::new();
    for x in (0..n_rows + n_cols).filter(|&x| linked[x]) {
        let r = root(&mut parent, x);
        if slot[r] == usize::MAX {
            slot[r] = parts.len();
            parts.push((Vec::new(), Vec::new()));
        }
        let part = &mut parts[slot[r]];
        if x < n_rows { part.0.push(x) } else { part.1.push(x - n_rows) }
    }
    parts
}

/// [`assign_with_miss`] solved component by component: the same contract (a distinct column or
/// a miss for every row, entries that are not finite forbidden), the edges being the finite
/// entries. A row with no finite entry is a miss. Solved whole up to [`WHOLE_UP_TO_ROWS`] rows.
pub fn assign_with_miss_by_components(
    cost: &[f64],
    n_rows: usize,
    n_cols: usize,
    miss_cost: &[f64],
) -> Vec<Option<usize>> {
    assert_eq!(cost.len(), n_rows * n_cols);
    assert_eq!(miss_cost.len(), n_rows);
    if n_rows <= WHOLE_UP_TO_ROWS {
        return assign_with_miss(cost, n_rows, n_cols, miss_cost);
    }
    let mut out = vec![None; n_rows];
    let mut sub = Vec::new();
    for (rows, cols) in components(n_rows, n_cols, |r, c| cost[r * n_cols + c].is_finite()) {
        sub.clear();
        sub.extend(rows.iter().flat_map(|&r| cols.iter().map(move |&c| cost[r * n_cols + c])));
        let miss: Vec<f64> = rows.iter().map(|&r| miss_cost[r]).collect();
        for (k, col) in assign_with_miss(&sub, rows.len(), cols.len(), &miss).into_iter().enumerate() {
            out[rows[k]] = col.map(|c| cols[c]);
        }
    }
    out
}

/// The optimal assignment of the `n_rows` rows into the `n_cols ≥ n_rows` columns of a matrix of
/// finite costs in which every entry at or above `cut` equals `cut` (as OSPA's `min(d, c)^p`
/// against `c^p`), solved component by component over the entries below `cut`. Returns, for each
/// row, its column when the row is paired below the cut, `None` when it is paired at the cut
/// (to any column: every such pairing costs `cut`, so the total is that of [`solve`] on the
/// whole matrix). Solved whole up to [`WHOLE_UP_TO_ROWS`] rows.
pub fn solve_below_cut(cost: &[f64], n_rows: usize, n_cols: usize, cut: f64) -> Vec<Option<usize>> {
    assert!(n_rows <= n_cols, "assignment needs rows <= cols");
    assert_eq!(cost.len(), n_rows * n_cols);
    if n_rows <= WHOLE_UP_TO_ROWS {
        let whole = solve(cost, n_rows, n_cols).into_iter().enumerate();
        return whole.map(|(r, c)| (cost[r * n_cols + c] < cut).then_some(c)).collect();
    }
    let mut out = vec![None; n_rows];
    let mut sub = Vec::new();
    for (rows, cols) in components(n_rows, n_cols, |r, c| cost[r * n_cols + c] < cut) {
        // Inside a component either side may be the larger: the smaller one is assigned.
        sub.clear();
        if rows.len() <= cols.len() {
            sub.extend(rows.iter().flat_map(|&r| cols.iter().map(move |&c| cost[r * n_cols + c])));
            for (k, c) in solve(&sub, rows.len(), cols.len()).into_iter().enumerate() {
                if sub[k * cols.len() + c] < cut {
                    out[rows[k]] = Some(cols[c]);
                }
            }
        } else {
            sub.extend(cols.iter().flat_map(|&c| rows.iter().map(move |&r| cost[r * n_cols + c])));
            for (k, r) in solve(&sub, cols.len(), rows.len()).into_iter().enumerate() {
                if sub[k * rows.len() + r] < cut {
                    out[rows[r]] = Some(cols[k]);
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Stream;

    /// Rows and columns scattered over a square, an edge where they lie within `gate` of each
    /// other: many small components, some rows and columns in none. The cost is the distance (in
    /// a plane, so that no two pairings tie exactly, as they would on a line).
    fn scattered(rng: &mut Stream, n: usize, m: usize, spread: f64, gate: f64) -> Vec<f64> {
        let mut point = || (rng.uniform() * spread, rng.uniform() * spread);
        let xs: Vec<(f64, f64)> = (0..n).map(|_| point()).collect();
        let ys: Vec<(f64, f64)> = (0..m).map(|_| point()).collect();
        xs.iter()
            .flat_map(|x| ys.iter().map(move |y| (x.0 - y.0).hypot(x.1 - y.1)))
            .map(|d| if d <= gate { d } else { f64::INFINITY })
            .collect()
    }

    fn total(cost: &[f64], m: usize, miss: &[f64], sol: &[Option<usize>]) -> f64 {
        let mut used = vec![false; m];
        sol.iter()
            .enumerate()
            .map(|(r, c)| match c {
                Some(c) => {
                    assert!(cost[r * m + c].is_finite() && !used[*c], "row {r}: column {c} forbidden or taken");
                    used[*c] = true;
                    cost[r * m + c]
                }
                None => miss[r],
            })
            .sum()
    }

    #[test]
    fn components_of_a_hand_made_graph() {
        // Edges: r0–c1, r2–c1, r2–c3, r3–c0; r1 and c2 have none.
        let edges = [(0, 1), (2, 1), (2, 3), (3, 0)];
        let parts = components(4, 4, |r, c| edges.contains(&(r, c)));
        assert_eq!(parts, vec![(vec![0, 2], vec![1, 3]), (vec![3], vec![0])]);
    }

    /// Split or whole, the gated assignment has the same optimal total and, on these
    /// continuous costs (no ties), the same pairs.
    #[test]
    fn the_split_gated_assignment_equals_the_whole() {
        let mut rng = Stream::new(29, &[crate::rng::domain::TEST]);
        let (mut split_problems, mut shared_parts) = (0, 0);
        for trial in 0..200 {
            // Half the problems are solved whole (up to WHOLE_UP_TO_ROWS rows), half split.
            let (n, m) = (1 + trial % 64, 1 + (trial * 7) % 71);
            let cost = scattered(&mut rng, n, m, 12.0 * (n.max(m) as f64 / 20.0).sqrt(), 1.5);
            let parts = components(n, m, |r, c| cost[r * m + c].is_finite());
            split_problems += usize::from(n > WHOLE_UP_TO_ROWS && parts.len() > 1);
            shared_parts += parts.iter().filter(|(rows, cols)| rows.len() > 1 && cols.len() > 1).count();
            let miss = vec![1.5 * ((n.min(m) + 1) as f64); n];
            let whole = assign_with_miss(&cost, n, m, &miss);
            let split = assign_with_miss_by_components(&cost, n, m, &miss);
            let (a, b) = (total(&cost, m, &miss, &whole), total(&cost, m, &miss, &split));
            assert!((a - b).abs() <= 1e-9 * a.abs().max(1.0), "trial {trial}: {a} vs {b}");
            assert_eq!(whole, split, "trial {trial}");
        }
        // The cases are mixed: problems in several parts, parts with contention inside.
        assert!(split_problems > 80 && shared_parts > 50, "{split_problems} split, {shared_parts} shared");
    }

    /// Split below the cut or solved whole on `min(cost, cut)`, the total and the pairs below the
    /// cut are the same.
    #[test]
    fn the_split_cut_assignment_equals_the_whole() {
        let mut rng = Stream::new(31, &[crate::rng::domain::TEST]);
        for trial in 0..200 {
            // Half the problems are solved whole (up to WHOLE_UP_TO_ROWS rows), half split.
            let n = 1 + trial % 64;
            let m = n + (trial * 5) % 13;
            let cut = 2.0;
            let spread = 10.0 * (m as f64 / 20.0).sqrt();
            let cost: Vec<f64> = scattered(&mut rng, n, m, spread, 1e9).into_iter().map(|d| d.min(cut)).collect();
            let whole = solve(&cost, n, m);
            let split = solve_below_cut(&cost, n, m, cut);
            let whole_total: f64 = whole.iter().enumerate().map(|(r, &c)| cost[r * m + c]).sum();
            let mut used = vec![false; m];
            let split_total: f64 = split
                .iter()
                .enumerate()
                .map(|(r, c)| match c {
                    Some(c) => {
                        assert!(cost[r * m + c] < cut && !used[*c]);
                        used[*c] = true;
                        cost[r * m + c]
                    }
                    None => cut,
                })
                .sum();
            assert!((whole_total - split_total).abs() <= 1e-9 * whole_total.max(1.0), "trial {trial}");
            let below: Vec<Option<usize>> =
                whole.iter().enumerate().map(|(r, &c)| (cost[r * m + c] < cut).then_some(c)).collect();
            assert_eq!(below, split, "trial {trial}");
        }
    }
}
