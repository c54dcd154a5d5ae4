//! The planning job queue: a pool of workers that claim queued plans from SQLite, run the
//! planner on blocking threads (off the async runtime), report progress, honour cancellation,
//! and store the result or the error. A panic in a planner fails that plan only.

use std::collections::HashMap;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use serde_json::Value;
use tokio::sync::{Notify, watch};
use tokio::task::JoinHandle;

use crate::planner::vehicle::Vehicle;
use crate::planner::{self, FieldLimits, MissionGeometry, PlanError, PlanOutput, PlanParams};
use crate::store::{Db, plans};

/// The function a worker runs for a job: `planner::plan` in production.
pub type Runner = Arc<dyn Fn(&plans::Job, &dyn planner::Progress) -> Result<PlanOutput, PlanError> + Send + Sync>;

/// The geometry of a mission snapshot stored with a plan.
pub fn snapshot_geometry(mission: &Value) -> MissionGeometry<'_> {
    MissionGeometry {
        area: mission.get("area").unwrap_or(&Value::Null),
        no_fly_zones: mission.get("no_fly_zones").filter(|v| !v.is_null()),
        obstacles: mission.get("obstacles").filter(|v| !v.is_null()),
        home: mission.get("home").and_then(|h| serde_json::from_value::<[f64; 2]>(h.clone()).ok()),
    }
}

/// The vehicle profiles of a snapshot, as they were when the plan was queued (older plans:
/// the built-ins).
pub fn snapshot_profiles(mission: &Value) -> Result<Vec<Vehicle>, String> {
    match mission.get("vehicles") {
        Some(v) => serde_json::from_value(v.clone()).map_err(|e| format!("stored vehicle profile is unreadable: {e}")),
        None => Ok(planner::vehicle::builtin_profiles()),
    }
}

/// Runs a stored job with the real planner.
pub fn plan_job(job: &plans::Job, limits: &FieldLimits, progress: &dyn planner::Progress) -> Result<PlanOutput, PlanError> {
    let params: PlanParams = serde_json::from_value(job.params.clone()).map_err(|e| PlanError::Infeasible(format!("stored parameters are unreadable: {e}")))?;
    let profiles = snapshot_profiles(&job.mission).map_err(PlanError::Infeasible)?;
    planner::plan(&snapshot_geometry(&job.mission), &params, &profiles, limits, progress)
}

struct RunningJob {
    cancel: Arc<AtomicBool>,
    requeue: Arc<AtomicBool>,
}

pub struct JobQueue {
    db: Db,
    runner: Runner,
    wake: Notify,
    running: Mutex<HashMap<String, RunningJob>>,
    stopping: watch::Sender<bool>,
    alive: AtomicUsize,
    /// Holds each job this long after claiming it (a test knob: makes "killed while running"
    /// reproducible). Zero in production.
    start_delay: Duration,
}

impl JobQueue {
    /// Starts `workers` workers.
    pub fn start(db: Db, workers: usize, runner: Runner, start_delay: Duration) -> (Arc<JobQueue>, Vec<JoinHandle<()>>) {
        let queue =
            Arc::new(JobQueue { db, runner, wake: Notify::new(), running: Mutex::new(HashMap::new()), stopping: watch::channel(false).0, alive: AtomicUsize::new(0), start_delay });
        let handles = (0..workers.max(1))
            .map(|_| {
                let q = queue.clone();
                q.alive.fetch_add(1, Ordering::SeqCst);
                tokio::spawn(async move {
                    q.work().await;
                    q.alive.fetch_sub(1, Ordering::SeqCst);
                })
            })
            .collect();
        (queue, handles)
    }

    /// Number of workers still taking jobs.
    pub fn workers_alive(&self) -> usize {
        self.alive.load(Ordering::SeqCst)
    }

    /// Tells idle workers that a job was queued.
    pub fn notify(&self) {
        self.wake.notify_waiters();
        self.wake.notify_one();
    }

    /// Asks a running job to stop (it was cancelled in the store already).
    pub fn cancel(&self, id: &str) {
        if let Some(job) = self.running.lock().expect("lock").get(id) {
            job.cancel.store(true, Ordering::SeqCst);
        }
    }

    /// Stops taking jobs, lets running ones finish for `grace`, then interrupts the rest and
    /// puts them back in the queue for the next start.
    pub async fn shutdown(&self, handles: Vec<JoinHandle<()>>, grace: Duration) {
        self.stopping.send_replace(true);
        self.wake.notify_waiters();
        let mut all = futures_join(handles);
        if tokio::time::timeout(grace, &mut all).await.is_err() {
            for job in self.running.lock().expect("lock").values() {
                job.requeue.store(true, Ordering::SeqCst);
                job.cancel.store(true, Ordering::SeqCst);
            }
            let _ = tokio::time::timeout(Duration::from_secs(10), all).await;
        }
    }

    async fn work(&self) {
        let mut stopping = self.stopping.subscribe();
        loop {
            if *stopping.borrow() {
                return;
            }
            match plans::claim_next(&self.db).await {
                Ok(Some(job)) => self.run(job).await,
                Ok(None) => {
                    tokio::select! {
                        _ = self.wake.notified() => {}
                        _ = tokio::time::sleep(Duration::from_secs(2)) => {}
                        _ = stopping.changed() => {}
                    }
                }
                Err(e) => {
                    tracing::error!(error = %e, "claiming a job failed");
                    tokio::time::sleep(Duration::from_secs(1)).await;
                }
            }
        }
    }

    async fn run(&self, job: plans::Job) {
        let cancel = Arc::new(AtomicBool::new(false));
        let requeue = Arc::new(AtomicBool::new(false));
        self.running.lock().expect("lock").insert(job.id.clone(), RunningJob { cancel: cancel.clone(), requeue: requeue.clone() });
        let progress = Arc::new(AtomicU64::new(0f64.to_bits()));
        let id = job.id.clone();
        tracing::info!(plan = %id, "plan started");
        let task = {
            let (runner, progress, cancel, delay) = (self.runner.clone(), progress.clone(), cancel.clone(), self.start_delay);
            tokio::task::spawn_blocking(move || {
                let report = |f: f64| {
                    progress.store(f.clamp(0.0, 1.0).to_bits(), Ordering::Relaxed);
                    !cancel.load(Ordering::Relaxed)
                };
                let mut waited = Duration::ZERO;
                while waited < delay && !cancel.load(Ordering::Relaxed) {
                    std::thread::sleep(Duration::from_millis(20));
                    waited += Duration::from_millis(20);
                }
                catch_unwind(AssertUnwindSafe(|| runner(&job, &report)))
            })
        };
        tokio::pin!(task);
        let mut tick = tokio::time::interval(Duration::from_millis(250));
        let mut reported = 0f64;
        let outcome = loop {
            tokio::select! {
                out = &mut task => break out,
                _ = tick.tick() => {
                    let p = f64::from_bits(progress.load(Ordering::Relaxed));
                    if p > reported {
                        reported = p;
                        if let Err(e) = plans::set_progress(&self.db, &id, p).await {
                            tracing::warn!(plan = %id, error = %e, "progress not saved");
                        }
                    }
                }
            }
        };
        let stored = match outcome {
            Ok(Ok(Ok(output))) => match serde_json::to_value(&output.stats) {
                Ok(stats) => {
                    let trajectory = serde_json::to_string(&output.trajectory).unwrap_or_default();
                    plans::succeed(&self.db, &id, &stats, &trajectory).await
                }
                Err(e) => plans::fail(&self.db, &id, &format!("the plan's figures could not be stored: {e}")).await,
            },
            Ok(Ok(Err(PlanError::Cancelled))) if requeue.load(Ordering::SeqCst) => plans::requeue(&self.db, &id).await,
            Ok(Ok(Err(PlanError::Cancelled))) => Ok(()),
            Ok(Ok(Err(e))) => plans::fail(&self.db, &id, &e.to_string()).await,
            Ok(Err(panic)) => {
                let what = panic.downcast_ref::<&str>().map(|s| s.to_string()).or_else(|| panic.downcast_ref::<String>().cloned()).unwrap_or_else(|| "unknown cause".into());
                tracing::error!(plan = %id, panic = %what, "planner panicked");
                plans::fail(&self.db, &id, &format!("internal error in the planner ({what}); the plan was not made")).await
            }
            Err(e) => plans::fail(&self.db, &id, &format!("the planning task was lost: {e}")).await,
        };
        if let Err(e) = stored {
            tracing::error!(plan = %id, error = %e, "the outcome of a plan could not be stored");
        }
        self.running.lock().expect("lock").remove(&id);
        tracing::info!(plan = %id, "plan ended");
    }
}

/// Waits for every handle.
fn futures_join(handles: Vec<JoinHandle<()>>) -> std::pin::Pin<Box<dyn std::future::Future<Output = ()> + Send>> {
    Box::pin(async move {
        for h in handles {
            let _ = h.await;
        }
    })
}
