//! What the numeric routines refuse: sizes that do not fit a plan.

/// An array or grid of the wrong size for the routine it was given to.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum NumericError {
    #[error("{what}: a {rows} × {cols} grid has no transform (both sides must be at least 1)")]
    EmptyGrid {
        what: &'static str,
        rows: usize,
        cols: usize,
    },
    #[error(
        "{what}: a {map_rows} × {map_cols} map does not fit the {grid_rows} × {grid_cols} \
         transform grid"
    )]
    MapTooLarge {
        what: &'static str,
        map_rows: usize,
        map_cols: usize,
        grid_rows: usize,
        grid_cols: usize,
    },
    #[error("{what}: {got} values given, {expected} expected")]
    Length {
        what: &'static str,
        expected: usize,
        got: usize,
    },
}
