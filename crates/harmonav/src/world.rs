//! [`World`]: what a [`Navigator`] needs of its workspace, so that one navigator serves the two
//! navigation transformations of `Θ = σ∘φ_k∘Φ` (`docs/maths.md` §10, §13): a star world
//! ([`StarWorld`], `Φ = T` the star bands of the workspace's boundary and obstacles) and a floor
//! plan ([`crate::FloorWorld`], `Φ = S∘M_a∘H∘B` through the harmonic map of its walls).
//!
//! A world gives `Θ` and `∇Θ`, the certified clearance `d(x)`, admits an obstacle, takes a
//! scan's event, leads the robot out of a margin band or boundary layer, and has its own rest
//! policy (a star world steps off a rest point of the hold, [`crate::Mode::FromRest`]; a floor
//! plan follows its shortest path out of a stall, [`crate::Mode::Escaping`]). The trait is
//! sealed: its methods are the navigator's, and a new world is a change to this crate.
//! [`Navigator::command`] is monomorphised over it: no `dyn` in the control path.

use std::borrow::Cow;
use std::fmt;

use harmonav_field::FieldEval;
use harmonav_transform::StarShape;
use nalgebra::Vector2;

use crate::error::NavError;
use crate::hold::Command;
use crate::navigator::{Controller, Navigator};
use crate::options::Options;
use crate::scan::ScanEvent;
use crate::scanning::ScanState;
use crate::space::Space;

pub use crate::floor::FloorWorld;
pub use crate::star::StarWorld;

/// A workspace a [`Navigator`] navigates: a star world ([`StarWorld`]) or a floor plan
/// ([`FloorWorld`]). Sealed. Its `Θ`, read through [`Navigator::field`], is a
/// [`harmonav_field::Field`] or a [`harmonav_floorplan::FloorField`].
pub trait World: Rules + Clone + fmt::Debug {}

impl World for StarWorld {}
impl World for FloorWorld {}

/// What a [`Navigator`] is built on ([`Navigator::new`]): the workspace's true boundary (a
/// [`StarShape`], giving a [`StarWorld`]) or a floor plan's solved map
/// (`Arc<`[`crate::FloorMap`]`>`, giving a [`FloorWorld`]). Sealed.
pub trait IntoWorld: Build {}

impl<T: Build> IntoWorld for T {}

/// The sealed half of [`IntoWorld`]: builds the world.
pub trait Build {
    /// The world it builds.
    type World: World;
    /// The world towards `goal` (finite) for `controller` under `options` (validated), with its
    /// empty scan perception and the controller in a world of its size
    /// (`Controller::in_world`).
    ///
    /// # Errors
    /// As [`Navigator::new`].
    fn build(
        self,
        goal: Vector2<f64>,
        controller: Controller,
        options: &Options,
    ) -> Result<(Self::World, ScanState, Controller), NavError>;
}

/// The sealed half of [`World`]: the navigator's steps that differ between the worlds. The
/// steps both share are [`Navigator`]'s own.
pub trait Rules: Sized {
    /// `Θ` over this world's known obstacles, with its free space as the hold sees it.
    type Field: Space + fmt::Debug;
    /// What a successful command leaves for [`Rules::after`] (a floor plan's escape).
    type Step;
    /// `Θ` (read only).
    fn field(&self) -> &Self::Field;
    /// `Θ`, `∇Θ` and the direction at `x` with the navigator's errors (`options`: the robot's
    /// size, to tell a boundary layer from a collision).
    fn eval(&self, x: Vector2<f64>, options: &Options) -> Result<FieldEval, NavError>;
    /// The known obstacles, grown by `radius + margin`, in the navigator's order.
    fn known(&self) -> Cow<'_, [StarShape]>;
    /// `k` of `phi_k`.
    fn k(&self) -> f64;
    /// Admits the grown obstacle `grown` (validated before anything changes); its index.
    ///
    /// # Errors
    /// The world is then unchanged: the shape overlaps another, crosses the boundary (or
    /// reaches a floor plan's boundary layer), or contains the goal.
    fn admit(&mut self, grown: StarShape) -> Result<usize, NavError>;
    /// Takes a scan's event: the obstacles become `event.obstacles`.
    ///
    /// # Errors
    /// As [`Rules::admit`], the world unchanged.
    fn sensed(&mut self, event: &ScanEvent, options: &Options) -> Result<(), NavError>;
    /// A discovery (an obstacle admitted or a scan's event) resets the world's own state.
    fn discovered(&mut self) {}
    /// The command to hold at `(x, ẋ)` and what it leaves for [`Rules::after`].
    ///
    /// # Errors
    /// As [`Navigator::command`].
    fn held(
        nav: &Navigator<Self>,
        x: Vector2<f64>,
        v: Vector2<f64>,
    ) -> Result<(Command, Self::Step), NavError>;
    /// After a successful command at `x`.
    fn after(nav: &mut Navigator<Self>, x: Vector2<f64>, step: Self::Step);
}
