//! stub
pub struct ContactProblem;
pub struct CurveOptions;
pub struct Snapshot;
pub struct Step;
pub fn solve_curve() {}
