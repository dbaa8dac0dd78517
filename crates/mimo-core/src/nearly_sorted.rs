//! Sorting what is nearly sorted already: the tables are written in the order dwells end while
//! their ids count in the order they start, so ids come a few rows out of place (docs/design.md
//! §3). An insertion sort puts them right in one pass plus the displacements; a table far from
//! order falls back to the library sort, so the worst case stays `n log n`.

/// Sort `v` ascending. The result is `v.sort()`'s; the cost is `n` plus the rows' total
/// displacement while that stays below `8 n`.
pub fn sort_nearly_sorted<T: Ord>(v: &mut [T]) {
    let budget = v.len().saturating_mul(8);
    let mut moved = 0usize;
    for i in 1..v.len() {
        let mut j = i;
        while j > 0 && v[j] < v[j - 1] {
            v.swap(j, j - 1);
            j -= 1;
            moved += 1;
        }
        if moved > budget {
            v.sort();
            return;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sorts_like_the_library_sort() {
        // Nearly sorted (each element a few places out), reversed (falls back), with repeats.
        let near: Vec<u64> = (0..1000u64).map(|i| i + [0, 3, 1, 5, 2][(i % 5) as usize] * 7 % 11).collect();
        let reversed: Vec<u64> = (0..5000u64).rev().collect();
        let repeats: Vec<(u64, u32)> = (0..300u32).map(|i| (u64::from(i % 7), i)).collect();
        for v in [near, reversed] {
            let (mut a, mut b) = (v.clone(), v);
            sort_nearly_sorted(&mut a);
            b.sort();
            assert_eq!(a, b);
        }
        let (mut a, mut b) = (repeats.clone(), repeats);
        sort_nearly_sorted(&mut a);
        b.sort();
        assert_eq!(a, b);
    }
}
