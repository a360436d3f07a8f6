//! Lending a planning problem to Python for the duration of one call.
//!
//! A Python motion planner receives an `opengrasp.Problem` whose methods (validity checks,
//! goal tests, ...) use the Rust [`PlanningProblem`] the harness built on its stack. Python
//! may keep the object after `plan` returns (and drop it on any thread), so the object holds
//! only a shared slot that [`lend_problem`] fills before the call and empties after it — also
//! when the call unwinds — and every access goes through [`Lent::with`], which fails once the
//! slot is empty or when called from another thread than the lending one.
//!
//! This is the crate's only unsafe code: dereferencing the lent pointer (and declaring the
//! slot `Send`/`Sync`). It is sound because (1) the pointer is only set while the borrow it
//! came from is alive (the slot is emptied by a drop guard before `lend_*` returns), (2) it
//! is only dereferenced on the lending thread, inside the lending call, where that borrow is
//! usable (the checker need not be `Sync`), and (3) [`Lent::with`] gives the closure a
//! reference that cannot outlive the closure.
#![allow(unsafe_code)]

use std::sync::{Arc, Mutex, PoisonError};
use std::thread::ThreadId;

use opengrasp_motion::problem::{PlanningProblem, SetupContext};

/// What is lent: a planning query or a setup context (lifetimes erased; see the module docs).
#[derive(Clone, Copy)]
enum Target {
    Problem(*const PlanningProblem<'static>),
    Setup(*const SetupContext<'static>),
}

/// The lent pointer and the thread that may use it.
#[derive(Clone, Copy)]
struct Slot {
    target: Target,
    thread: ThreadId,
}

// SAFETY: a `Slot` is only dereferenced on `thread` (checked in `Lent::with`); moving or
// sharing the pointer value itself between threads is harmless.
unsafe impl Send for Slot {}

/// A borrowed query or setup context, valid for the closure given to [`Lent::with`].
pub enum Borrowed<'a> {
    /// `MotionPlanner::plan`'s problem.
    Problem(&'a PlanningProblem<'a>),
    /// `MotionPlanner::setup`'s context.
    Setup(&'a SetupContext<'a>),
}

/// Why a lent value cannot be used.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unavailable {
    /// The lending call is over.
    Expired,
    /// Called from another thread than the lending one.
    WrongThread,
}

/// The slot a Python `Problem` reads through; empty outside the lending call.
#[derive(Clone)]
pub struct Lent(Arc<Mutex<Option<Slot>>>);

/// Empties the slot when dropped (also on unwind).
struct Reset(Lent);

impl Drop for Reset {
    fn drop(&mut self) {
        *self.0 .0.lock().unwrap_or_else(PoisonError::into_inner) = None;
    }
}

fn lend<R>(target: Target, f: impl FnOnce(Lent) -> R) -> R {
    let slot = Slot { target, thread: std::thread::current().id() };
    let lent = Lent(Arc::new(Mutex::new(Some(slot))));
    let _reset = Reset(lent.clone());
    f(lent)
}

/// Calls `f` with a slot holding `problem`; the slot is empty once this returns.
// The second cast changes only the lifetime, which clippy does not see.
#[allow(clippy::unnecessary_cast)]
pub fn lend_problem<R>(problem: &PlanningProblem<'_>, f: impl FnOnce(Lent) -> R) -> R {
    lend(Target::Problem(problem as *const PlanningProblem<'_> as *const PlanningProblem<'static>), f)
}

/// Calls `f` with a slot holding `context`; the slot is empty once this returns.
#[allow(clippy::unnecessary_cast)]
pub fn lend_setup<R>(context: &SetupContext<'_>, f: impl FnOnce(Lent) -> R) -> R {
    lend(Target::Setup(context as *const SetupContext<'_> as *const SetupContext<'static>), f)
}

impl Lent {
    /// Calls `f` with the lent value, if the lending call is still running on this thread.
    pub fn with<R>(&self, f: impl for<'a> FnOnce(Borrowed<'a>) -> R) -> Result<R, Unavailable> {
        // Held during `f`, so the slot cannot be emptied meanwhile (`f` never re-enters).
        let guard = self.0.lock().unwrap_or_else(PoisonError::into_inner);
        let slot = guard.ok_or(Unavailable::Expired)?;
        if slot.thread != std::thread::current().id() {
            return Err(Unavailable::WrongThread);
        }
        Ok(match slot.target {
            // SAFETY: the slot holds the pointer only while the lending call, and so the
            // borrow it was made from, is alive, and we are on the lending thread (module
            // docs); the higher-ranked closure cannot keep the reference.
            Target::Problem(p) => f(Borrowed::Problem(unsafe { &*p })),
            // SAFETY: as above.
            Target::Setup(p) => f(Borrowed::Setup(unsafe { &*p })),
        })
    }

    /// True while the lent value may be used from this thread.
    pub fn is_active(&self) -> bool {
        self.with(|_| ()).is_ok()
    }
}
