//! Stopping a long computation: a flag its caller raises (a cancelled job) and an optional
//! deadline (a time limit). Once [`Stop::requested`] answers true it never answers false
//! again, so a stage may cut its work short after it and rely on [`crate::plan`] throwing
//! the result away.
//!
//! ```
//! use std::time::{Duration, Instant};
//! use coverplan_planner::Stop;
//!
//! let stop = Stop::until(Instant::now() + Duration::from_secs(60));
//! assert!(!stop.requested());
//! let for_the_worker = stop.clone();
//! stop.request();
//! assert!(for_the_worker.requested() && !for_the_worker.timed_out());
//! ```

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// Shared by clones: raising one raises all.
#[derive(Debug, Clone, Default)]
pub struct Stop {
    raised: Arc<AtomicBool>,
    deadline: Option<Instant>,
}

impl Stop {
    /// Stops only when asked.
    pub fn never() -> Self {
        Stop::default()
    }

    /// Stops when asked or at `deadline`.
    pub fn until(deadline: Instant) -> Self {
        Stop { deadline: Some(deadline), ..Stop::default() }
    }

    /// Asks every holder to stop.
    pub fn request(&self) {
        self.raised.store(true, Ordering::Relaxed);
    }

    /// True once asked or past the deadline.
    pub fn requested(&self) -> bool {
        self.raised.load(Ordering::Relaxed) || self.timed_out()
    }

    /// True past the deadline.
    pub fn timed_out(&self) -> bool {
        self.deadline.is_some_and(|d| Instant::now() >= d)
    }

    pub fn deadline(&self) -> Option<Instant> {
        self.deadline
    }
}
