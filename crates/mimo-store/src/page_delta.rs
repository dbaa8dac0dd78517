//! The Parquet delta encoding (`DELTA_BINARY_PACKED`) of 64-bit integers decoded from one page,
//! for the page decoder ([`crate::page_columns`]): the writer stores the id columns (`Delta`
//! storage, docs/architecture.md) this way.
//!
//! The layout (Parquet format, "Delta encoding"): a header of ULEB128 values — values per block,
//! miniblocks per block, value count — and the first value (zigzag ULEB128); then blocks, each
//! the minimum delta (zigzag ULEB128), one bit width per miniblock and the miniblocks, each
//! holding its values' `delta − min_delta` bit-packed, least significant bit first. A miniblock
//! not needed by the last values is absent (its bit width is still listed). Values add with
//! wrapping arithmetic; unsigned columns store the bits of their `u64`.

/// One ULEB128 value at `pos` (advanced past it).
fn uleb(bytes: &[u8], pos: &mut usize) -> Option<u64> {
    let mut value = 0u64;
    for shift in (0..64).step_by(7) {
        let byte = *bytes.get(*pos)?;
        *pos += 1;
        value |= u64::from(byte & 0x7f) << shift;
        if byte & 0x80 == 0 {
            return Some(value);
        }
    }
    None
}

/// A zigzag-encoded signed value.
fn zigzag(v: u64) -> i64 {
    ((v >> 1) as i64) ^ -((v & 1) as i64)
}

/// Value `j` of `width` bits of a bit-packed miniblock.
fn unpack(mini: &[u8], j: usize, width: usize) -> Option<u64> {
    if width == 0 {
        return Some(0);
    }
    let bit = j * width;
    let first = bit / 8;
    let mut window = [0u8; 16];
    let end = (first + 16).min(mini.len());
    window[..end.checked_sub(first)?].copy_from_slice(mini.get(first..end)?);
    let v = u128::from_le_bytes(window) >> (bit % 8);
    let mask = if width == 64 { u64::MAX } else { (1u64 << width) - 1 };
    Some(v as u64 & mask)
}

/// The `n` values of a delta-encoded page appended to `out`; `None` when the page is malformed or
/// holds another count.
pub(crate) fn decode_u64s(page: &[u8], n: usize, out: &mut Vec<u64>) -> Option<()> {
    let mut pos = 0;
    let block = usize::try_from(uleb(page, &mut pos)?).ok()?;
    let minis = usize::try_from(uleb(page, &mut pos)?).ok()?;
    let total = usize::try_from(uleb(page, &mut pos)?).ok()?;
    let mut last = zigzag(uleb(page, &mut pos)?);
    if total != n || minis == 0 || block == 0 || !block.is_multiple_of(minis) || !(block / minis).is_multiple_of(8) {
        return None;
    }
    if total == 0 {
        return Some(());
    }
    let per_mini = block / minis;
    out.reserve(total);
    out.push(last as u64);
    let mut left = total - 1;
    while left > 0 {
        let min_delta = zigzag(uleb(page, &mut pos)?);
        let widths = page.get(pos..pos + minis)?;
        pos += minis;
        for &width in widths {
            if left == 0 {
                break;
            }
            let width = usize::from(width);
            if width > 64 {
                return None;
            }
            let len = per_mini * width / 8;
            let mini = page.get(pos..pos + len)?;
            pos += len;
            let take = per_mini.min(left);
            for j in 0..take {
                last = last.wrapping_add(min_delta).wrapping_add(unpack(mini, j, width)? as i64);
                out.push(last as u64);
            }
            left -= take;
        }
    }
    Some(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A hand-made page: block of 8 values in 1 miniblock, 5 values 7, 9, 8, 12, 12: deltas
    /// 2, −1, 4, 0, min delta −1, packed `delta + 1` = 3, 0, 5, 1 in 3 bits.
    #[test]
    fn a_hand_made_page_decodes() {
        // header: block 8, 1 miniblock, 5 values, first 7 (zigzag 14)
        let mut page = vec![8, 1, 5, 14];
        // min delta −1 (zigzag 1), width 3
        page.extend([1, 3]);
        // 3, 0, 5, 1, then padding: bits 011 000 101 001 000 000 000 000, LSB first
        let bits: u32 = 3 | (5 << 6) | (1 << 9);
        page.extend(&bits.to_le_bytes()[..3]);
        let mut out = Vec::new();
        decode_u64s(&page, 5, &mut out).expect("decodes");
        assert_eq!(out, [7, 9, 8, 12, 12]);
        assert!(decode_u64s(&page, 4, &mut Vec::new()).is_none(), "a count other than the header's");
        assert!(decode_u64s(&page[..6], 5, &mut Vec::new()).is_none(), "a short page");
    }
}
