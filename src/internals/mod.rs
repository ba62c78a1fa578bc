//! The engine below the library API: influence coefficients, operators,
//! executors, the contact iteration, the adaptive mesh, the analysis of a
//! solved contact, quadrature and charts. Public for the tests, benches and
//! examples that check the engine piece by piece; no stability promise. A
//! program uses [`crate::problem`] and the other top-level modules, which
//! re-export the few engine types they take or return.

#[path = "../analysis/mod.rs"]
pub mod analysis;
#[path = "../backend/mod.rs"]
pub mod backend;
#[path = "../gauss.rs"]
pub mod gauss;
#[path = "../kernel/mod.rs"]
pub mod kernel;
#[path = "../mesh/mod.rs"]
pub mod mesh;
#[path = "../operator/mod.rs"]
pub mod operator;
#[path = "../plot/mod.rs"]
pub mod plot;
#[path = "../solver/mod.rs"]
pub mod solver;
