//! The Slurm executor (`--executor slurm`): every stage a plan must run
//! becomes a batch job chained to its inputs' jobs; see [`executor`].
pub mod executor;
mod partition;
mod settings;

pub use executor::{
    JobSpec, JobStatus, PipelineRun, SlurmRun, Submission, SubmittedJob, scancel, squeue, status,
    submit, wait,
};
pub use settings::*;
