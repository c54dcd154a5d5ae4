//! The planning job queue: a pool of workers that claim queued plans from the database, run the
//! planner on blocking threads (off the async runtime), report progress, honour cancellation
//! and time limits, and store the result or the error. A panic in a planner fails that plan only.
//!
//! Several replicas may share one PostgreSQL queue. Each claim carries a lease that the running
//! job's heartbeat renews; a plan whose replica died is requeued by any replica once its lease
//! has run out, and a heartbeat that finds its plan cancelled (on any replica) stops the job.

use std::collections::HashMap;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use serde::Deserialize;
use serde_json::{Value, json};
use tokio::sync::{Notify, watch};
use tokio::task::JoinHandle;
use tracing::Instrument;

use crate::planner::geojson::FeatureCollection;
use crate::planner::params::AltitudeReference;
use crate::planner::params::resume::{Resume, ResumeParams};
use crate::planner::patrol::PatrolParams;
use crate::planner::terrain::ElevationModel;
use crate::planner::vehicle::Vehicle;
use crate::planner::{self, FieldLimits, MissionGeometry, PlanError, PlanParams, Stop};
use crate::store::{Db, plans, terrain};
use crate::telemetry::Telemetry;

/// The function a worker runs for a job: `planner::plan` in production. It should return soon
/// after its [`Stop`] is raised or times out; a worker that waited [`ABANDON_AFTER`] past the
/// time limit gives up on it and takes the next job.
pub type Runner = Arc<dyn Fn(&plans::Job, &JobRequest, &dyn planner::Progress, &Stop) -> Result<JobOutput, PlanError> + Send + Sync>;

/// A stored job's request, read once when a worker takes it: the parameters, typed, and the
/// vehicle profiles of its snapshot.
#[derive(Debug, Clone)]
pub struct JobRequest {
    pub params: JobParams,
    pub profiles: Vec<Vehicle>,
    /// A resumed plan: where the original's flight stopped, and the original's trajectory.
    pub resume: Option<(Resume, FeatureCollection)>,
}

// one per running job: boxing would save nothing worth an allocation
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone)]
pub enum JobParams {
    Plan(PlanParams),
    Patrol(PatrolParams),
}

impl JobRequest {
    /// The job's request; a record this server cannot read is its own fault, said in words.
    pub fn read(job: &plans::Job) -> Result<JobRequest, String> {
        let unreadable = |e: serde_json::Error| format!("stored parameters are unreadable: {e}");
        let params = match job.kind {
            plans::JobKind::Patrol => JobParams::Patrol(serde_json::from_value(job.params.clone()).map_err(unreadable)?),
            plans::JobKind::Plan => JobParams::Plan(serde_json::from_value(job.params.clone()).map_err(unreadable)?),
        };
        Ok(JobRequest { params, profiles: snapshot_profiles(&job.mission)?, resume: snapshot_resume(&job.mission)? })
    }

    /// The method it is planned with, for log lines and metrics.
    fn label(&self) -> &'static str {
        match &self.params {
            JobParams::Patrol(_) => planner::patrol::PLANNER_ID,
            JobParams::Plan(params) => planner::method_id(params, &self.profiles).unwrap_or("refused request"),
        }
    }

    /// The time limit the request asks for, if any.
    fn time_limit(&self) -> Option<Duration> {
        let asked = match &self.params {
            JobParams::Plan(params) => params.time_limit_s,
            JobParams::Patrol(_) => None,
        };
        asked.filter(|s| s.is_finite() && *s > 0.0).map(Duration::from_secs_f64)
    }

    /// A plan flown at a height above the mission's elevation model.
    fn flies_over_terrain(&self) -> bool {
        matches!(&self.params, JobParams::Plan(p) if p.altitude_reference == Some(AltitudeReference::Terrain))
    }
}

/// What a finished job stores: its figures and its GeoJSON.
#[derive(Debug, Clone)]
pub struct JobOutput {
    pub stats: Value,
    pub trajectory: String,
}

/// How often a running job renews its lease, saves its progress and looks whether it was
/// cancelled elsewhere.
pub const HEARTBEAT: Duration = Duration::from_millis(500);

/// How long past its time limit a worker waits for a planner that does not stop before
/// failing the plan without it (its thread is left to finish on its own).
pub const ABANDON_AFTER: Duration = Duration::from_millis(500);

pub use crate::config::QueueSettings;

/// The vehicle profiles of a snapshot, as they were when the plan was queued (older plans:
/// the built-ins).
pub fn snapshot_profiles(mission: &Value) -> Result<Vec<Vehicle>, String> {
    match mission.get("vehicles") {
        Some(v) => serde_json::from_value(v.clone()).map_err(|e| format!("stored vehicle profile is unreadable: {e}")),
        None => Ok(planner::vehicle::builtin_profiles()),
    }
}

/// The resume a snapshot holds (`resume`: the request and the original's trajectory), checked.
pub fn snapshot_resume(mission: &Value) -> Result<Option<(Resume, FeatureCollection)>, String> {
    let Some(resume) = mission.get("resume") else { return Ok(None) };
    let request = ResumeParams::deserialize(&resume["request"]).map_err(|e| format!("stored resume request is unreadable: {e}"))?;
    let request = request.check().map_err(|e| format!("stored resume request: {e}"))?;
    let trajectory = FeatureCollection::deserialize(&resume["trajectory"]).map_err(|e| format!("stored trajectory to resume is unreadable: {e}"))?;
    Ok(Some((request, trajectory)))
}

/// Runs a stored job with the real planner.
pub fn plan_job(job: &plans::Job, request: &JobRequest, limits: &FieldLimits, progress: &dyn planner::Progress, stop: &Stop) -> Result<JobOutput, PlanError> {
    let geometry = MissionGeometry::of(&job.mission);
    let profiles = &request.profiles;
    let (stats, trajectory) = match &request.params {
        JobParams::Patrol(params) => {
            let out = planner::patrol::patrol(&geometry, params, profiles, limits, stop)?;
            (json!(out.stats), out.trajectory.to_string())
        }
        JobParams::Plan(params) => {
            let model = job.terrain.as_ref().map(|(name, bytes)| ElevationModel::read(bytes, name)).transpose()?;
            let geometry = MissionGeometry { terrain: model.as_ref(), ..geometry };
            let out = match &request.resume {
                Some((resume, original)) => planner::resume(&geometry, params, profiles, limits, original, resume, progress, stop)?,
                None => planner::plan(&geometry, params, profiles, limits, progress, stop)?,
            };
            (json!(out.stats), serde_json::to_string(&out.trajectory).unwrap_or_default())
        }
    };
    Ok(JobOutput { stats, trajectory })
}

struct RunningJob {
    stop: Stop,
    requeue: Arc<AtomicBool>,
}

pub struct JobQueue {
    db: Db,
    /// This process's name in the claims it makes.
    pub replica: String,
    runner: Runner,
    wake: Notify,
    running: Mutex<HashMap<String, RunningJob>>,
    stopping: watch::Sender<bool>,
    alive: AtomicUsize,
    settings: QueueSettings,
    /// Job counts and durations for `/metrics`.
    pub telemetry: Arc<Telemetry>,
}

impl JobQueue {
    /// Starts `workers` workers.
    pub fn start(db: Db, workers: usize, runner: Runner, settings: QueueSettings) -> (Arc<JobQueue>, Vec<JoinHandle<()>>) {
        let queue = Arc::new(JobQueue {
            db,
            replica: settings.replica.clone().unwrap_or_else(|| format!("{}-{}", hostname(), &uuid::Uuid::new_v4().simple().to_string()[..8])),
            runner,
            wake: Notify::new(),
            running: Mutex::new(HashMap::new()),
            stopping: watch::channel(false).0,
            alive: AtomicUsize::new(0),
            settings,
            telemetry: Telemetry::new(),
        });
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
        tokio::spawn(queue.clone().requeue_abandoned());
        if let Db::Postgres(pool) = &queue.db {
            tokio::spawn(listen_for_queued(pool.clone(), Arc::downgrade(&queue), queue.stopping.subscribe()));
        }
        (queue, handles)
    }

    /// Every third of a lease, puts the plans of replicas that stopped renewing their leases back
    /// in the queue, until the queue stops.
    async fn requeue_abandoned(self: Arc<Self>) {
        let mut stopping = self.stopping.subscribe();
        loop {
            tokio::select! {
                _ = tokio::time::sleep(self.settings.lease / 3) => {}
                _ = stopping.changed() => return,
            }
            match plans::requeue_abandoned(&self.db, false).await {
                Ok((requeued, failed)) if requeued + failed > 0 => {
                    tracing::warn!(requeued, failed, "plans whose replica stopped renewing their lease");
                    self.notify();
                }
                Ok(_) => {}
                Err(e) => tracing::warn!(error = %e, "looking for abandoned plans failed"),
            }
        }
    }

    /// Number of workers still taking jobs.
    pub fn workers_alive(&self) -> usize {
        self.alive.load(Ordering::SeqCst)
    }

    /// Plans being planned now.
    pub fn running_count(&self) -> usize {
        self.running.lock().expect("lock").len()
    }

    /// Tells idle workers that a job was queued.
    pub fn notify(&self) {
        self.wake.notify_waiters();
        self.wake.notify_one();
    }

    /// Asks a running job to stop (it was cancelled in the store already).
    pub fn cancel(&self, id: &str) {
        if let Some(job) = self.running.lock().expect("lock").get(id) {
            job.stop.request();
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
                job.stop.request();
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
            match plans::claim_next(&self.db, &self.replica, self.settings.lease.as_secs_f64()).await {
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

    /// The time this job may take: the queue's limit, or the plan's own when shorter.
    fn time_limit(&self, request: &JobRequest) -> Duration {
        request.time_limit().map_or(self.settings.time_limit, |a| a.min(self.settings.time_limit))
    }

    /// Runs a job; every log line it writes carries its plan id and tenant.
    async fn run(&self, job: plans::Job) {
        let span = tracing::info_span!("job", plan = %job.id, tenant = %job.tenant);
        self.run_in_span(job).instrument(span).await
    }

    async fn run_in_span(&self, mut job: plans::Job) {
        let request = match JobRequest::read(&job) {
            Ok(request) => request,
            Err(why) => {
                tracing::error!(%why, "a stored plan request cannot be read");
                let claim = plans::Claim { plan: &job.id, replica: &self.replica };
                let detail = format!("this server could not read the stored request ({why}); the plan was not made");
                if let Err(e) = plans::fail(&self.db, claim, "internal", &detail).await {
                    tracing::error!(error = %e, "the outcome of a plan could not be stored");
                }
                self.telemetry.job("unreadable request", "failed", Duration::ZERO);
                return;
            }
        };
        if request.flies_over_terrain() {
            match terrain::model(&self.db, &job.tenant, &job.mission_id).await {
                Ok(model) => job.terrain = model,
                // the planner then says the mission has no model to follow
                Err(e) => tracing::error!(error = %e, "the mission's elevation model could not be read"),
            }
        }
        let limit = self.time_limit(&request);
        let planner = request.label();
        let started = tokio::time::Instant::now();
        let stop = Stop::until(started.into_std() + self.settings.start_delay + limit);
        let requeue = Arc::new(AtomicBool::new(false));
        self.running.lock().expect("lock").insert(job.id.clone(), RunningJob { stop: stop.clone(), requeue: requeue.clone() });
        let progress = Arc::new(AtomicU64::new(0f64.to_bits()));
        let id = job.id.clone();
        tracing::info!(%planner, time_limit_s = limit.as_secs_f64(), "plan started");
        let task = {
            let (runner, progress, stop, delay) = (self.runner.clone(), progress.clone(), stop.clone(), self.settings.start_delay);
            let span = tracing::Span::current();
            tokio::task::spawn_blocking(move || {
                let _in_job = span.enter();
                let report = |f: f64| {
                    progress.store(f.clamp(0.0, 1.0).to_bits(), Ordering::Relaxed);
                    !stop.requested()
                };
                let mut waited = Duration::ZERO;
                while waited < delay && !stop.requested() {
                    std::thread::sleep(Duration::from_millis(20));
                    waited += Duration::from_millis(20);
                }
                catch_unwind(AssertUnwindSafe(|| runner(&job, &request, &report, &stop)))
            })
        };
        tokio::pin!(task);
        let abandon_at = started + self.settings.start_delay + limit + ABANDON_AFTER;
        let mut heartbeat = tokio::time::interval(HEARTBEAT);
        let claim = plans::Claim { plan: &id, replica: &self.replica };
        let outcome = loop {
            tokio::select! {
                out = &mut task => break Some(out),
                _ = tokio::time::sleep_until(abandon_at) => break None,
                _ = heartbeat.tick() => {
                    let p = f64::from_bits(progress.load(Ordering::Relaxed));
                    match plans::heartbeat(&self.db, claim, p, self.settings.lease.as_secs_f64()).await {
                        // cancelled (here or on another replica), or taken over: stop
                        Ok(false) => stop.request(),
                        Ok(true) => {}
                        Err(e) => tracing::warn!(error = %e, "heartbeat not saved"),
                    }
                }
            }
        };
        let over_time = format!("the plan took longer than its time limit of {} s and was stopped", limit.as_secs_f64());
        let timed_out = || plans::fail(&self.db, claim, "time_limit", &over_time);
        let (ended, stored) = match outcome {
            None => {
                tracing::error!("the planner did not stop at its time limit; its thread was left behind");
                ("time_limit", timed_out().await)
            }
            Some(Ok(Ok(Ok(output)))) => ("succeeded", plans::succeed(&self.db, claim, &output.stats, &output.trajectory).await),
            Some(Ok(Ok(Err(PlanError::Cancelled)))) if requeue.load(Ordering::SeqCst) => ("requeued", plans::requeue(&self.db, claim).await),
            // a plan cancelled by its owner is marked so already; one that ran out of time is not
            Some(Ok(Ok(Err(PlanError::Cancelled)))) if stop.timed_out() => ("time_limit", timed_out().await),
            Some(Ok(Ok(Err(PlanError::Cancelled)))) => ("cancelled", plans::release(&self.db, claim, "cancelled").await),
            Some(Ok(Ok(Err(PlanError::Input(e))))) => ("failed", plans::fail(&self.db, claim, e.code, &e.to_string()).await),
            Some(Ok(Ok(Err(e)))) => ("failed", plans::fail(&self.db, claim, "infeasible", &e.to_string()).await),
            Some(Ok(Err(panic))) => {
                let what = crate::panic_message(&*panic);
                tracing::error!(panic = %what, "planner panicked");
                ("failed", plans::fail(&self.db, claim, "internal", &format!("internal error in the planner ({what}); the plan was not made")).await)
            }
            Some(Err(e)) => ("failed", plans::fail(&self.db, claim, "internal", &format!("the planning task was lost: {e}")).await),
        };
        if let Err(e) = stored {
            tracing::error!(error = %e, "the outcome of a plan could not be stored");
        }
        self.running.lock().expect("lock").remove(&id);
        self.telemetry.job(planner, ended, started.elapsed());
        tracing::info!(outcome = ended, seconds = started.elapsed().as_secs_f64(), "plan ended");
    }
}

/// Wakes idle workers whenever any replica queues a plan (PostgreSQL's `LISTEN`), until the
/// queue stops (the listener's connection must be back in the pool before it closes); the
/// workers' slow poll covers the moments the listener is reconnecting.
async fn listen_for_queued(pool: sqlx::PgPool, queue: std::sync::Weak<JobQueue>, mut stopping: watch::Receiver<bool>) {
    loop {
        let listening = async {
            let mut listener = sqlx::postgres::PgListener::connect_with(&pool).await?;
            listener.listen(plans::QUEUED_CHANNEL).await?;
            loop {
                listener.recv().await?;
                match queue.upgrade() {
                    Some(q) => q.notify(),
                    None => return Ok::<(), sqlx::Error>(()),
                }
            }
        };
        tokio::select! {
            biased;
            _ = stopping.changed() => return,
            ended = listening => match ended {
                Ok(()) => return,
                Err(e) => tracing::warn!(error = %e, "listening for queued plans failed; retrying in 1 s"),
            },
        }
        tokio::select! {
            _ = tokio::time::sleep(Duration::from_secs(1)) => {}
            _ = stopping.changed() => return,
        }
    }
}

/// The machine's name, for the replica names in claims.
fn hostname() -> String {
    std::fs::read_to_string("/etc/hostname").map(|h| h.trim().to_owned()).ok().filter(|h| !h.is_empty()).unwrap_or_else(|| "coverplan".into())
}

/// Waits for every handle.
fn futures_join(handles: Vec<JoinHandle<()>>) -> std::pin::Pin<Box<dyn std::future::Future<Output = ()> + Send>> {
    Box::pin(async move {
        for h in handles {
            let _ = h.await;
        }
    })
}
