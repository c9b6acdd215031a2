//! The inertial-platform error model of Liu, Liu & Su (2009) as the project reads it
//! (`docs/model.md`), its switchable effects, the paper's vehicle test, a truth simulator and
//! the dataset format. Each module cites the equations of `docs/model.md` it implements.
//!
//! The second model family, a strapdown unit's ([`strapdown`]), has its physics here so far:
//! attitude, state equations and their Jacobian on dual numbers ([`dual`]); see
//! docs/model.md, "The strapdown family".
//!
//! The [`PlatformModel`] implements [`SystemModel`], the trait every filter is generic over.
//! Effects ([`Effect`]) add coefficients and terms at run time: the state dimension is 20
//! plus what they add.

pub mod attitude;
pub mod batch_propagation;
pub mod dataset;
pub mod declared;
pub mod dual;
pub mod earth;
pub mod effect;
pub mod effect_spec;
pub mod effects;
pub mod error;
pub mod family;
pub mod input_cursor;
pub mod input_file;
pub mod instruction_set;
pub mod integrate;
pub mod kinematics;
pub mod linear_rates;
pub mod memory;
pub mod model;
pub mod model_kind;
pub mod noise;
pub mod outside;
pub mod partials;
pub mod partials_check;
pub mod prior;
pub mod real;
pub mod rng;
pub mod segments;
pub mod sensor_classes;
pub mod sensor_faults;
pub mod sensors;
pub mod simulate;
pub mod state;
pub mod strapdown;
pub mod system;
pub mod trajectory;
pub mod trig;

pub use attitude::Attitude;
pub use effect::{
    BlockGroup, DynEffect, Effect, MeasurementTerm, NoiseChannel, Partials, PhysicalBound, Terms,
};
pub use effects::Registry;
pub use error::DynamicsError;
pub use family::{FamilyModel, ModelKind, TruthSimulation};
pub use input_cursor::InputCursor;
pub use integrate::{InputWindow, PropagationScratch};
pub use kinematics::{Input, Kinematics, LatitudeTerms};
pub use linear_rates::{Feature, LinearRate};
pub use model::PlatformModel;
pub use noise::NoiseConfig;
pub use prior::PlatformPrior;
pub use real::{Lanes, Real};
pub use sensors::MeasurementModel;
pub use simulate::{Prior, SimulatedRun, Simulator, TruthConfig};
pub use system::SystemModel;
pub use trajectory::{Trajectory, TrajectoryConfig};
