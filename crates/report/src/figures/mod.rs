//! The paper's figures, one file each, on the shared helpers of
//! [`plotting`].

pub mod colormap;
pub mod fig10;
pub mod fig11;
pub mod fig2;
pub mod fig4;
pub mod fig4b;
pub mod fig4d;
pub mod fig7;
pub mod fig8;
pub mod plotting;

pub use plotting::{Figure, Rendered, render};
