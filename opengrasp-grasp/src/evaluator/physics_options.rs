//! Options of the physics hold check ([`super::physics_check`]), with what each setting was
//! measured to do on the benchmark grasps.

use nalgebra::Vector3;
use opengrasp_core::hand::{Actuation, Hand};
use opengrasp_core::physics::PhysicsOptions;

use crate::error::{GraspError, Result};

/// Options of the physics check ([`super::physics_check`]).
///
/// Measured (`physics_sweep per_cell=5`, these defaults: armature 1e-3 kg·m², squeeze 0.3,
/// each hand driven as its actuation says, [`Self::hand_actuation`], adaptive steps
/// [`Self::adaptive_step`]): Barrett 55/79 held, ARMAR-III 38/80, none diverged; with the
/// normal step throughout (`adaptive_substeps=0`; every figure below unless it says
/// otherwise) Barrett 46/79, ARMAR-III 29/80 (30/80 before joints on their closing stop counted in the balanced grip,
/// when 59 of the 80 had none and fell back to position control at the full effort limits;
/// 23/80 under position control), none diverged; without the armature
/// (squeeze 0.4, position control) 42/79 (1 diverged), 12/80. The figures below were taken
/// without the armature unless they say otherwise.
/// Why the benchmark grasps fail (`physics_sweep per_cell=5`, without armature: Barrett 42/79
/// held, ARMAR-III 11/80): the grip, not gravity. 36 of Barrett's 37 failures and all 69 of
/// ARMAR-III's lose the object in the gravity-free control run as well
/// ([`super::PhysicsOutcome::grip_escapes`]); at the release their traced contact normal forces push
/// it with a median 17 (Barrett) and 11 (ARMAR-III) object weights that no friction inside the
/// cones cancels ([`super::PhysicsOutcome::release_push`]). Settings tried against it on ARMAR-III
/// (`hand=armar3 per_cell=3`, 7/48 held with these defaults): contacts at 100 Hz 4/48, at
/// 1 kHz 1/48 (2 diverged); joint stiffness 1e5 4/48; a 1 ms timestep 8/48, with `spring = 0.4`
/// and 1 kHz contacts 9/48; closing on the free object (`fixture` off) 6/48, with `spring = 0.4`
/// 5/48, `spring = 1` 1/48; `effort = 1` at 1 kHz 0/48 (33 diverged; 2 without the fixture),
/// `effort = 0.3` 0/48; thumb efforts 15 N·m instead of 5 N·m 7/48, fingers 1.67 N·m 6/48 (at
/// 30 Hz the contacts' softness, not the caps, sets the grip forces); the joints locked at the
/// release (position targets at the simulated positions, or 0.05 rad past them) 5/48, 4/48;
/// a quasi-static closing on the free, damped object ([`Self::closing_damping`]) 6–8/48.
#[derive(Clone, Debug, PartialEq)]
pub struct PhysicsCheckOptions {
    /// Directions of gravity tried one after the other (object frame), each in its own
    /// simulation continued from the common settled state. Default: the six axis directions
    /// ±x, ±y, ±z.
    pub directions: Vec<Vector3<f64>>,
    /// Magnitude of gravity (m/s²). Default: 9.81.
    pub gravity: f64,
    /// Time (s) the fingers squeeze without gravity before it is switched on. Default: 0.2.
    pub settle: f64,
    /// Simulated time per direction with gravity on (s). Default: 0.5.
    pub duration: f64,
    /// The closing joints (those with a non-zero closing velocity) are commanded this far (rad
    /// or m) beyond the closed configuration, so the motors keep pressing the fingers against
    /// the object (with the simulator's joint stiffness, capped at the joints' effort limits).
    /// Default: 0.3, as a hand told to close keeps squeezing past the first touch. At the 30 Hz
    /// contacts the grip force grows with how far the fingers sink in: with 0.05 the ARMAR-III
    /// fingers (8 g phalanges) pressed 7.9 N in total (median over 80 benchmark grasps), too
    /// little for friction to carry the objects' weight (μ ΣN / m g median 0.88); with 0.4
    /// they press 120–170 N, sinking about 15 mm into the object (Barrett 6–8 mm). Measured
    /// (`physics_sweep per_cell=5 iterations=16 armature=0 squeeze=…`, held/checked Barrett, ARMAR-III):
    /// 0.05: 28/79, 0/80; 0.2: 39/79, 6/80; 0.4: 42/79, 11/80; 1: 36/79, 6/80; 3 (to the
    /// joint limits): 35/79, 5/80. With the default armature (1e-3 kg·m², see
    /// [`Self::physics`]) the motors press harder for the same error (rapier's motor gains are
    /// accelerations, scaled by the joint inertia), so less squeeze is needed: 0.1: 35/79,
    /// 22/80; 0.2: 40/79, 23/80; 0.3 (the default): 46/79, 23/80; 0.4 (`hand=armar3 per_cell=3`)
    /// 9/48. Used only without `effort`.
    pub squeeze: f64,
    /// `Some(f)`: the closing joints are stall-torque actuators
    /// ([`opengrasp_core::physics::JointTarget::Effort`]): each of the hand's closing motors
    /// presses in its closing direction with `f` times its effort limit whatever the finger
    /// position, its torque shared by the joints it drives (with
    /// [`PhysicsOptions::coupled_actuators`], by virtual work as in the static hold test).
    /// Needs stiff contacts (`physics.contact_frequency` ≈ 1000 Hz): a light phalanx pressed
    /// with force `F` sinks about `F / (m (2π f)²)` into the object. `None`: position control
    /// `squeeze` past the closed configuration; at the default 30 Hz the fingers reach that
    /// target by sinking into the soft contacts, so they press with the contacts' spring force
    /// rather than their effort limits. Default: `None`. Uniform stall torques do not balance
    /// fingers with several actuated joints and one contact (they roll along the object until
    /// a joint limit), so on the benchmark grasps they hold fewer objects than position
    /// control.
    pub effort: Option<f64>,
    /// `Some(f)`: balanced grip torques (takes precedence over `effort`). The closing joints
    /// press with the torques of [`super::grip::grip_torques`] (joint torques within `f` times
    /// their shares of the effort limits whose contact forces balance each other inside the
    /// friction cones shrunk by `grip_margin`, maximising the smallest normal force), each as an
    /// implicit stall torque: a position target `squeeze_beyond` past the closed configuration
    /// with the joint's motor force capped at `|τᵢ|` (rapier's implicit motor then presses
    /// with exactly `|τᵢ|` while stalled). Needs stiff contacts (as `effort`). Default: `None`.
    /// A grasp without any balanced grip (every torque zero: no squeeze of all finger contacts
    /// fits the cones and signs) is checked as without `balanced`.
    /// Measured (1 kHz contacts, `physics_sweep balanced=1 contact_hz=1000 per_cell=5`): the
    /// Barrett salt-can wrap holds in all six directions, but over the benchmark's
    /// force-closure palm grasps Barrett holds 15/79 (18/79 with `balanced = 0.3`; 25/79 at
    /// the default 30 Hz contacts) and ARMAR-III 0/80, no more than position control (26/79,
    /// 0/80 with the same sweep): the torques balance the evaluator's contacts, and where the
    /// simulated contacts differ (a palm contact that does not touch, fingertips that roll) the
    /// constant torques push the object out.
    /// With the default armature (30 Hz contacts, `physics_sweep per_cell=5 balanced=1`):
    /// Barrett 43/79, ARMAR-III 19/80 (position control 46/79, 23/80); as joint springs
    /// (`grip_compliance`) see there.
    /// Setting both `balanced` and `effort` is an error ([`PhysicsCheckOptions::validate`]).
    pub balanced: Option<f64>,
    /// `Some(θ)` (needs `balanced`): at the end of the squeeze (before the release), every
    /// motorised joint of the balanced grip becomes a force-based spring
    /// ([`super::grip::stiffen_grip`]) of stiffness `limitᵢ / θ` (N·m/rad; full effort share at
    /// θ of deflection) resting `τᵢ / stiffness` past the joint's simulated position: it keeps
    /// pressing with the balanced torque `τᵢ` there, and more or less as the object moves towards
    /// or away from the finger (a stable equilibrium instead of a neutral one). Default: `None`.
    /// Measured (`physics_sweep per_cell=5 balanced=1 compliance=0.05`, 30 Hz contacts): Barrett
    /// 33/79 held (2 diverged), ARMAR-III 11/80 with the explicit-torque springs, and the same
    /// with `resolve=1` (default position control 42/79, 11/80); before them 19/79, 0/80
    /// (position control then: 26/79, 0/80), with `resolve=1` the same, and 9/79 at 1 kHz
    /// contacts. The springs resist squeezing, not the sideways escape of fingertip grasps (the
    /// traced ARMAR-III salt-can grasp loses every contact within 40 ms). With the default
    /// armature (`physics_sweep per_cell=5 balanced=1 compliance=θ`): θ = 0.05 Barrett 35/79,
    /// ARMAR-III 29/80 (with `resolve=1` 35/79, 30/80; with `regrip=0.01` the same); θ = 0.1
    /// 36/79, 30/80; θ = 0.02 32/79, 27/80; `balanced = 0.3`, θ = 0.05 29/79, 29/80; ARMAR-III
    /// alone θ = 0.2 and 0.4 25/80 — the compliant actuation of the fluidic ARMAR-III hand
    /// ([`opengrasp_core::hand::Actuation::Compliant`], θ = 0.1), which position control beats
    /// on the Barrett (46/79).
    pub grip_compliance: Option<f64>,
    /// `Some(θ)`: the fingers close as under a position controller with a physical gain: every
    /// joint of a closing actuator is a spring ([`super::grip::stiffen_grip`] of
    /// [`super::grip::closing_grip`]) of stiffness `shareᵢ / θ` (N·m/rad) resting θ past the
    /// evaluated (touching) configuration, so it presses with its full effort share there, less
    /// as it closes further and more (up to the share) as the object pushes it back: the
    /// object, free with `fixture` off, centres itself between fingers whose forces balance.
    /// Excludes `effort` and `balanced`. Default: `None`. Measured (`physics_sweep per_cell=5
    /// spring=θ …`, held/checked Barrett, ARMAR-III; default position control 42/79, 11/80)
    /// since the rapier backend applies springs as explicit joint torques (before, a spring in
    /// a two-joint finger pressed with ≈ 3 % of its cap: a distal spring of 0.5 N·m on a 25 mm
    /// lever pushed 0.59 N instead of 20 N, `opengrasp-core/tests/spring_press.rs`): θ = 0.4
    /// 43/79, 12/80 (34/79 with 1 diverged, 4/80 before the fix); 0.2 39/79 (1 diverged),
    /// 14/80; 0.6 40/79, 10/80; 0.4 without fixture 47/79, 10/80 — none raises both hands
    /// clearly (with the default armature, θ = 0.4: 45/79, 22/80). A TorqueSwitch breakaway on top (each finger's inner closing joints locked by
    /// springs of 10 × their share at 1 mrad, the outermost pressing) held 24/79, 1/80. The
    /// grips that fail are out of balance by many times the weight (the fixture holds a median
    /// 11 weights on the ARMAR-III grasps): equal effort shares on every motor do not balance.
    pub spring: Option<f64>,
    /// With `balanced`: at the end of the squeeze the balanced grip is solved again on the
    /// simulator's contacts and joint positions ([`super::grip_sim::after_squeeze`]), so the
    /// torques balance the contacts the simulated fingers actually make (one per touching link,
    /// the palm's kept from the evaluation while the object is clamped: see
    /// [`super::grip_sim::simulated_evaluation`]). Default: false. Measured (`physics_sweep
    /// per_cell=5 balanced=1 resolve=1`): ARMAR-III 19/80, as without it. (Before the simulated
    /// contacts were merged per link and the clamped palm's kept, the re-solve found no grip on
    /// them and changed nothing.)
    pub resolve_grip: bool,
    /// `Some(Δ)` (needs `balanced`): a grip controller during the squeeze. Every `Δ` seconds of
    /// `settle` the balanced grip is solved again on the simulator's contacts and joint
    /// positions ([`super::grip_sim::simulated_evaluation`]) and commanded as the new stall
    /// torques, as a hand with tactile sensing re-balances its finger forces while it closes;
    /// the torques of the last solve then stay through the release and the gravity runs.
    /// Default: `None`: it holds no more than the grip solved once. Measured (`physics_sweep
    /// per_cell=5 balanced=1 regrip=0.01`, 30 Hz contacts, held/checked): ARMAR-III 17/80
    /// clamped (the grip solved once 19/80, position control 23/80), 19/80 on the damped free
    /// object (`fixture=0 tau=0.01`), with `balanced = 0.3` 17/80; Barrett 42/79 clamped, 39/79
    /// damped free (solved once 43/79, position control 46/79). The re-solved grips do squeeze
    /// (15–50 N smallest normal force on the traced ARMAR-III grasps), but constant torques
    /// balanced on the contacts of one instant leave the soft contacts' dynamics out.
    pub regrip: Option<f64>,
    /// Friction margin of the balanced grip: its contact forces stay inside cones of
    /// `grip_margin × μ`, leaving friction for gravity. Default: 0.5.
    pub grip_margin: f64,
    /// The object counts as held if gravity moves it less than this (m): the distance between
    /// its pose after `settle + duration` with gravity and its pose after the same time in a
    /// gravity-free control run (which cancels any squeeze-induced creep of the simulator).
    /// Default: 0.02.
    pub max_translation: f64,
    /// ... and turns it less than this (rad), measured the same way. Default: 0.35 (20°).
    pub max_rotation: f64,
    /// Clamp the object at its evaluated pose while the fingers squeeze during `settle` (as a
    /// table or fixture holds it while a real hand closes), then release it from rest: the
    /// fingers press on an immovable object, so the first to touch does not push it away and
    /// the squeeze does not sink the fingers into it. (Teleporting the object back every step
    /// instead let the fingers advance into it by the distance it was pushed each step: the
    /// contacts then released millimetres of penetration at once and threw objects out of
    /// the Barrett hand.) Default: true.
    pub fixture: bool,
    /// With `fixture`: time (s) over which the fixture lets go. `0`: at once (a step in the
    /// force on the object). Positive: the wrench the fixture exerts at the end of the squeeze
    /// ([`super::release::fixture_wrench`]) is applied to the freed object and ramped linearly
    /// to zero over this time ([`super::release::release_gradually`]), so the squeezing fingers
    /// take the object over quasi-statically. Default: 0: measured (`physics_sweep per_cell=5
    /// release=0.1`, held/checked Barrett, ARMAR-III) 22/79, 0/80 against 24/79, 0/80 at once
    /// (0.05 squeeze, 8 iterations); 40/79, 6/80 against 39/79, 6/80 (0.2 squeeze, 16
    /// iterations). Traced, the grips that fail are out of balance by many times the weight,
    /// which no release rate can fix.
    pub release: f64,
    /// `Some(τ)`: quasi-static closing on a free object (needs `fixture` off). While the
    /// fingers squeeze during `settle`, the object is free but feels viscous damping of time
    /// constant `τ` (s): the force `−(m / τ) v` and the torque `−(I / τ) ω`, as if it rested in
    /// a viscous medium (or slid on a table) while a real hand closes, so it drifts at about
    /// `F τ / m` under a net grip force `F` to where the finger forces balance, instead of
    /// being flung by the first finger to touch. The damping is then ramped to zero over
    /// `damping_ramp` before the gravity-free control run and the gravity runs.
    /// Default: `None`: it leaves the traced grip nearly balanced (median least push at the end
    /// of the closing 0.4 weights, `physics_sweep hand=armar3 per_cell=3 fixture=0 tau=0.01`,
    /// against 11 clamped) but holds no more (`physics_sweep per_cell=5 fixture=0 tau=0.01
    /// spring=0.2`: Barrett 38/79, ARMAR-III 13/80; the same spring undamped 38/79, 12/80; τ =
    /// 3 ms 39/79, 12/80; `hand=armar3 per_cell=3`, 7/48 with the defaults: τ = 1, 3, 10, 30,
    /// 100 ms 7, 7, 6, 7, 7/48, with `spring` 0.2, 0.4, 1 rad 8, 5, 1/48, with `squeeze` 0.1,
    /// 0.2 0/48, 4/48, with 1 ms steps and 100 or 300 Hz contacts 10/48, 9/48). Where the
    /// damped closing leaves the object (`physics_damped` example, τ = 10 ms, 5 grasps per
    /// cell; held/checked Barrett, ARMAR-III): pushed out of the grip 0/18, 0/30; still
    /// pressed but driven on by the grip alone once undamped 19/39, 4/42; settled 20/22, 7/8.
    /// The check fails where the simulated actuation (equal effort shares, position targets
    /// past the touch) has no equilibrium near the grasp, not where a settled grip meets gravity.
    /// With the default armature (`fixture=0 tau=0.01`): Barrett 43/79, ARMAR-III 22/80.
    pub closing_damping: Option<f64>,
    /// With `closing_damping`: time (s) over which the damping rate falls linearly from `1 / τ`
    /// to zero after `settle`. Default: 0.1.
    pub damping_ramp: f64,
    /// An object that is not held counts as dropped if gravity moved it farther than this
    /// (m), as slipped (it moved in the hand but stayed near it) otherwise. Default: 0.1.
    pub drop_translation: f64,
    /// Simulator settings (gravity is overridden; the hand's link friction is replaced by the
    /// object's friction coefficient, so the contacts have the μ the evaluator assumed).
    /// Default: [`PhysicsOptions::default`] with `contact_frequency` 30 Hz (rapier's own
    /// default): with stiffer contacts an object squeezed hard creeps through the grip by
    /// centimetres per second (a solver artefact, measured with rapier 0.30); and
    /// [`PhysicsOptions::coupled_actuators`] on, so each of the hand's motors drives its coupled
    /// joints with its own torque in total; [`PhysicsOptions::independent_chains`] on (each
    /// finger its own multibody: the same dynamics at half the cost; rounding differs from one
    /// multibody, which flipped 1 of 64 default-suite checks, a marginal Barrett green-cup grasp);
    /// and 16 solver iterations (rapier 0.30 takes one small step per iteration): with 8, 1 of
    /// 159 benchmark checks diverged at the 0.05 squeeze and 3 at 0.4, and Barrett held 29/79
    /// at 0.4 (42/79 with 16), for about 1.6× the check's CPU time; and
    /// [`PhysicsOptions::joint_armature`] 1e-3 kg·m²: the reflected inertia of a geared finger
    /// motor (a small DC rotor of about 1e-7 kg·m² behind a 100:1 gearbox), 12× a Barrett
    /// proximal phalanx's own inertia about its joint and about 250× an ARMAR-III one's, so the
    /// soft contacts see a heavier finger and it sinks and rolls less. Measured (`physics_sweep
    /// armature=…`, squeeze 0.4, `hand=armar3 per_cell=3`, 7/48 without): 1e-4 8/48, 1e-3 9/48,
    /// 1e-2 9/48; 1e-3 with 300 Hz contacts 10/48 (`per_cell=5`: 34/79 with 3 diverged, 15/80),
    /// with 1 kHz 7/48, with `fixture=0 tau=0.01` 11/48, with `spring=0.2` at 300 Hz 9/48;
    /// 1e-4 with squeeze 0.2 (`per_cell=5`) 39/79, 18/80. Most failures still lose the object
    /// in the gravity-free control run (the grip's imbalance, not gravity).
    pub physics: PhysicsOptions,
    /// `Some(w)`: the release is simulated finely ([`super::release::ReleaseWindow`]): the last
    /// `w.before` seconds of the squeeze, the release and `w.after` seconds of gravity-free grip
    /// after it run in steps of `w.timestep` with the contacts at `w.contact_frequency`, then
    /// the control run and the gravity runs continue from there with [`Self::physics`]'s step
    /// and contacts. The kick that throws the object out of the grip comes within 10–20 ms of
    /// the release, so the window costs a few dozen fine steps once per check (the runs
    /// start from its end). Default: `None`: it does not raise the hold rates. Measured
    /// (`physics_sweep per_cell=5 window_…`, held/checked Barrett, ARMAR-III; without a window
    /// 46/79, 29/80): 1 ms at 120 Hz, 20 ms before, 30 ms after 47/79, 29/80 (+3 % of the
    /// sweep's user time; `run grasp` 10.0 → 10.6 s user, its physics tallies moved both ways
    /// in 6 of the 32 cells); the same at 30 Hz 47/79, 30/80; 100 ms after 47/79, 29/80,
    /// 300 ms after 45/79, 26/80; the whole settle in the window (200 ms before) with 20, 40,
    /// 50, 100 ms after 45, 47, 52, 48/79 (each with 1 diverged) and 30, 31, 30, 31/80, at
    /// 30 Hz 46/79 (1 diverged), 29/80: the spread of marginal grasps, not a gain. The steps
    /// of the gravity runs are what counts: the 1 ms step throughout holds ARMAR-III 41/80 at
    /// 30 Hz and 38/80 at 120 Hz, a 2 ms step at 120 Hz 30/80, the default step at 120 Hz 25/80
    /// (`hand=armar3 timestep=… contact_hz=…`), but the 1 ms step costs ~4.5× the sweep's time.
    pub release_window: Option<super::release::ReleaseWindow>,
    /// `Some(a)`: in the control run and the gravity runs (after the release), each step that
    /// starts with the object moving at `a.speed` or faster in contact with the hand is split
    /// into `a.substeps` steps ([`super::AdaptiveStep`]). Default: `Some(AdaptiveStep::default())` (from 0.01 m/s, 3
    /// steps of about 1.4 ms): a grip in balance is not kicked out of it by the coarse step's
    /// overshoot into the soft contacts. Measured (`physics_sweep per_cell=5`, held/checked
    /// Barrett, ARMAR-III): 55/79, 38/80 against 46/79, 29/80 with the normal step, none
    /// diverged; the sweep's user time 37 → 69 s (contended two-core VM; 64 s with
    /// [`Self::early_drop`]) and `opengrasp run grasp` 13.9 → 26.0 s user with the early drop,
    /// its physics tallies 32 → 36 of 64 held. Splitting only steps in contact (not free
    /// flight) gave the same verdicts in every direction and the same `run grasp` tallies, at
    /// 58 s user for the sweep (less loaded VM) and `run grasp` 13.2 → 23.5 s user.
    pub adaptive_step: Option<super::AdaptiveStep>,
    /// Stop a gravity run as soon as its object is certainly dropped: out of the hand's reach,
    /// farther than `drop_translation` (and `max_translation`) from the control run's final
    /// pose, and moving away from both under gravity alone, so no later step can bring it back
    /// (the proof is in the source, `evaluator/stepping.rs`). The verdict is the one of the full
    /// run; the direction's translation and rotation are those at the stop (the distance of
    /// the centre of mass from the control's only grows after it). Default: true. Measured
    /// (`physics_sweep per_cell=5 verdicts=1`): every direction's verdict as without it, the
    /// sweep's user time 69.5 → 63.5 s (contended).
    pub early_drop: bool,
    /// Drive the fingers as the hand's actuators act ([`Hand::actuation`]) where these options
    /// choose no actuator model themselves (`effort`, `balanced`, `spring` and
    /// `grip_compliance` all `None`): a hand with [`Actuation::Compliant`] is checked with
    /// `balanced = Some(1.0)` and `grip_compliance = Some(compliance)` (the balanced grip
    /// pressed through joint springs), a hand with [`Actuation::Position`] under position
    /// control `squeeze` past the closed configuration. Default: true.
    pub hand_actuation: bool,
}

/// The six axis directions ±x, ±y, ±z: the default gravity directions of the physics check
/// and of the static hold test.
pub(crate) fn axis_directions() -> Vec<Vector3<f64>> {
    vec![Vector3::x(), -Vector3::x(), Vector3::y(), -Vector3::y(), Vector3::z(), -Vector3::z()]
}

impl Default for PhysicsCheckOptions {
    fn default() -> Self {
        Self {
            directions: axis_directions(),
            gravity: 9.81,
            settle: 0.2,
            duration: 0.5,
            squeeze: 0.3,
            effort: None,
            balanced: None,
            grip_margin: 0.5,
            grip_compliance: None,
            spring: None,
            resolve_grip: false,
            regrip: None,
            max_translation: 0.02,
            max_rotation: 0.35,
            drop_translation: 0.1,
            fixture: true,
            release: 0.0,
            closing_damping: None,
            damping_ramp: 0.1,
            physics: PhysicsOptions {
                contact_frequency: 30.0,
                solver_iterations: 16,
                coupled_actuators: true,
                independent_chains: true,
                joint_armature: 1e-3,
                ..PhysicsOptions::default()
            },
            release_window: None,
            adaptive_step: Some(super::AdaptiveStep::default()),
            early_drop: true,
            hand_actuation: true,
        }
    }
}

impl PhysicsCheckOptions {
    /// The options the check applies to `hand`: these, with the hand's own actuator model
    /// where `hand_actuation` asks for it (see [`Self::hand_actuation`]).
    pub fn for_hand(&self, hand: &Hand) -> Self {
        let mut options = self.clone();
        let chosen =
            self.effort.is_some() || self.balanced.is_some() || self.spring.is_some() || self.grip_compliance.is_some();
        if let (true, false, Actuation::Compliant { compliance }) = (self.hand_actuation, chosen, hand.actuation()) {
            options.balanced = Some(1.0);
            options.grip_compliance = Some(compliance);
        }
        options
    }

    /// Checks the scalar options and their combination.
    ///
    /// # Errors
    /// [`GraspError::InvalidParameter`] for a non-positive gravity, duration or threshold, a
    /// negative settle time, squeeze or release, `effort` and `balanced` set together (only one actuator
    /// model can drive the fingers), a `grip_compliance` that is not finite and positive or
    /// is set without `balanced`, or a bad `release_window` ([`super::release::ReleaseWindow::validate`],
    /// or longer before the release than `settle`), or a bad `adaptive_step`
    /// ([`super::AdaptiveStep::validate`]).
    pub fn validate(&self) -> Result<()> {
        for (name, v) in [
            ("gravity", self.gravity),
            ("duration", self.duration),
            ("max_translation", self.max_translation),
            ("max_rotation", self.max_rotation),
            ("drop_translation", self.drop_translation),
        ] {
            crate::planners::check_positive(name, v)?;
        }
        for (name, v) in [
            ("settle", self.settle),
            ("squeeze", self.squeeze),
            ("release", self.release),
            ("damping_ramp", self.damping_ramp),
        ] {
            crate::planners::check_non_negative(name, v)?;
        }
        if self.effort.is_some() && self.balanced.is_some() {
            return Err(GraspError::InvalidParameter {
                name: "effort",
                reason: "`effort` and `balanced` exclude each other: set one".into(),
            });
        }
        if let Some(theta) = self.spring {
            crate::planners::check_positive("spring", theta)?;
            if self.effort.is_some() || self.balanced.is_some() {
                return Err(GraspError::InvalidParameter {
                    name: "spring",
                    reason: "excludes `effort` and `balanced` (only one actuator model can drive the fingers)".into(),
                });
            }
        }
        if let Some(tau) = self.closing_damping {
            crate::planners::check_positive("closing_damping", tau)?;
            if self.fixture {
                return Err(GraspError::InvalidParameter {
                    name: "closing_damping",
                    reason: "needs `fixture` off (the damped object is free while the fingers close)".into(),
                });
            }
        }
        if let Some(adaptive) = &self.adaptive_step {
            adaptive.validate()?;
        }
        if let Some(window) = &self.release_window {
            window.validate()?;
            if window.before > self.settle {
                return Err(GraspError::InvalidParameter {
                    name: "release_window.before",
                    reason: format!("{} s exceeds the settle time {} s", window.before, self.settle),
                });
            }
        }
        // Options that act on the balanced grip, and why each needs it.
        let needs_balanced = |name: &'static str, set: bool, why: &str| {
            if set && self.balanced.is_none() {
                return Err(GraspError::InvalidParameter { name, reason: format!("needs `balanced` ({why})") });
            }
            Ok(())
        };
        needs_balanced("resolve_grip", self.resolve_grip, "it re-solves the balanced grip")?;
        if let Some(interval) = self.regrip {
            crate::planners::check_positive("regrip", interval)?;
        }
        needs_balanced("regrip", self.regrip.is_some(), "it re-solves the balanced grip")?;
        if let Some(theta) = self.grip_compliance {
            crate::planners::check_positive("grip_compliance", theta)?;
        }
        needs_balanced("grip_compliance", self.grip_compliance.is_some(), "the springs' preload is the balanced grip")?;
        Ok(())
    }
}
