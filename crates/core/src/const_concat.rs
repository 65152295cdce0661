//! Joining constant slices at compile time: how a derived `Schema`'s columns
//! and a `#[params]` struct's keys take in those of the blocks flattened into
//! them (`#[column(flatten)]`, `#[param(flatten)]`). Written with `while`
//! loops because iterators are not usable in a `const fn`.

/// How many items the parts hold together.
#[doc(hidden)]
pub const fn total_len<T>(parts: &[&[T]]) -> usize {
    let (mut n, mut i) = (0, 0);
    while i < parts.len() {
        n += parts[i].len();
        i += 1;
    }
    n
}

/// The parts' items in order, as one array of `N` = [`total_len`] items
/// (`filler` only initialises the array; every slot is overwritten).
#[doc(hidden)]
pub const fn concat<T: Copy, const N: usize>(parts: &[&[T]], filler: T) -> [T; N] {
    let mut out = [filler; N];
    let (mut k, mut i) = (0, 0);
    while i < parts.len() {
        let mut j = 0;
        while j < parts[i].len() {
            out[k] = parts[i][j];
            k += 1;
            j += 1;
        }
        i += 1;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const PARTS: &[&[&str]] = &[&["a"], &[], &["b", "c"]];

    #[test]
    fn parts_are_joined_in_order() {
        const ALL: [&str; total_len(PARTS)] = concat(PARTS, "");
        assert_eq!(ALL, ["a", "b", "c"]);
    }
}
