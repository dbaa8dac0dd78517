//! The order in which the scorer walks the rows of the truth and tracks tables: by run, then by
//! target or track, then by time, then (tracks) by the rank the table gives rows of one track at
//! one time (`mimo_core::table_rules::track_row_order`: `n_updates`, the deleted row last), ties
//! kept in table order (the readers refuse tables with such ties, so none is left) — the order of a stable sort on
//! those columns (`sort([run, key, t_s])` with `maintain_order` in polars terms), found
//! without comparing strings per row: the rows are put in buckets by (run, key) in table
//! order, the buckets sorted by key, and a bucket sorted (stably) by time only when its times
//! are not already in order (each table file's times are, docs/design.md §7).

use std::cmp::Ordering;
use std::collections::HashMap;
use std::hash::Hash;

/// Times compared as a total order compares finite floats (`-0.0 == 0.0`); the tables'
/// times are checked finite before.
fn by_time(a: f64, b: f64) -> Ordering {
    a.partial_cmp(&b).unwrap_or(Ordering::Equal)
}

/// The row indices in the order of a stable sort by (`run`, `key`, `t_s`, `rank`), `rank` 0 for
/// every row when `None`.
pub(crate) fn stable_order<K: Ord + Hash + Copy>(
    run: &[u32],
    key: &[K],
    t_s: &[f64],
    rank: Option<&[u64]>,
) -> Vec<usize> {
    let rank_of = |i: usize| rank.map_or(0, |r| r[i]);
    let cmp = |a: usize, b: usize| by_time(t_s[a], t_s[b]).then(rank_of(a).cmp(&rank_of(b)));
    let mut slot: HashMap<(u32, K), usize> = HashMap::new();
    let mut buckets: Vec<((u32, K), Vec<usize>)> = Vec::new();
    let mut last: Option<((u32, K), usize)> = None;
    for (i, (&r, &k)) in run.iter().zip(key).enumerate() {
        let b = match last {
            Some((lk, b)) if lk == (r, k) => b,
            _ => {
                let next = buckets.len();
                let b = *slot.entry((r, k)).or_insert(next);
                if b == next {
                    buckets.push(((r, k), Vec::new()));
                }
                last = Some(((r, k), b));
                b
            }
        };
        buckets[b].1.push(i);
    }
    buckets.sort_unstable_by_key(|b| b.0);
    let mut order = Vec::with_capacity(run.len());
    for (_, mut rows) in buckets {
        let ordered = rows.windows(2).all(|w| cmp(w[0], w[1]) != Ordering::Greater);
        if !ordered {
            rows.sort_by(|&a, &b| cmp(a, b));
        }
        order.extend(rows);
    }
    order
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The order is that of a stable sort of the rows by (run, key, time), on rows with
    /// repeated keys, times out of order within a key and equal times (ties keep table order).
    #[test]
    fn the_order_of_a_stable_sort_by_run_key_and_time() {
        let n = 500;
        let run: Vec<u32> = (0..n).map(|i| (i * 7 % 3) as u32).collect();
        let key: Vec<u64> = (0..n).map(|i| (i * 13 % 5) as u64).collect();
        let t_s: Vec<f64> = (0..n).map(|i| ((i * 31) % 17) as f64 * 0.5).collect();
        let mut want: Vec<usize> = (0..n).collect();
        want.sort_by(|&a, &b| (run[a], key[a]).cmp(&(run[b], key[b])).then(by_time(t_s[a], t_s[b])));
        let got = stable_order(&run, &key, &t_s, None);
        assert_eq!(got, want);
        // With a rank, rows at one time of one key follow it, whatever their table order.
        let rank: Vec<u64> = (0..n).map(|i| ((i * 11) % 7) as u64).collect();
        let mut want: Vec<usize> = (0..n).collect();
        want.sort_by(|&a, &b| {
            (run[a], key[a]).cmp(&(run[b], key[b])).then(by_time(t_s[a], t_s[b])).then(rank[a].cmp(&rank[b]))
        });
        assert_eq!(stable_order(&run, &key, &t_s, Some(&rank)), want);
        // Times in table order within each key: the buckets alone give the order.
        let t_sorted: Vec<f64> = (0..n).map(|i| i as f64).collect();
        let mut want: Vec<usize> = (0..n).collect();
        want.sort_by_key(|&a| (run[a], key[a]));
        assert_eq!(stable_order(&run, &key, &t_sorted, None), want);
    }
}
