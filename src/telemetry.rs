//! What `/metrics` tells Prometheus: requests by route and status with their latency, the queue
//! and the running jobs, and job durations by planner and outcome. One registry per server (no
//! global), encoded in the OpenMetrics text format, which Prometheus reads.

use std::sync::Arc;
use std::time::Duration;

use prometheus_client::encoding::EncodeLabelSet;
use prometheus_client::metrics::counter::Counter;
use prometheus_client::metrics::family::Family;
use prometheus_client::metrics::gauge::Gauge;
use prometheus_client::metrics::histogram::{Histogram, exponential_buckets};
use prometheus_client::registry::Registry;

#[derive(Clone, Debug, Hash, PartialEq, Eq, EncodeLabelSet)]
struct RouteLabels {
    method: String,
    /// The route's template (`/api/v1/plans/{id}`), so that ids do not make new series.
    route: String,
    status: u16,
}

#[derive(Clone, Debug, Hash, PartialEq, Eq, EncodeLabelSet)]
struct LatencyLabels {
    method: String,
    route: String,
}

#[derive(Clone, Debug, Hash, PartialEq, Eq, EncodeLabelSet)]
struct JobLabels {
    planner: String,
    /// succeeded, failed, time_limit, cancelled, requeued
    outcome: String,
}

type Histograms<L> = Family<L, Histogram, fn() -> Histogram>;

pub struct Telemetry {
    registry: Registry,
    requests: Family<RouteLabels, Counter>,
    latency: Histograms<LatencyLabels>,
    jobs: Family<JobLabels, Counter>,
    job_seconds: Histograms<JobLabels>,
    queued: Gauge,
    running: Gauge,
}

/// Request latencies: 0.5 ms to about 16 s.
fn latency_buckets() -> Histogram {
    Histogram::new(exponential_buckets(0.0005, 2.0, 16))
}

/// Job durations: 10 ms to about 20 min.
fn job_buckets() -> Histogram {
    Histogram::new(exponential_buckets(0.01, 2.0, 18))
}

impl Telemetry {
    pub fn new() -> Arc<Self> {
        let mut registry = Registry::with_prefix("coverplan");
        let requests = Family::<RouteLabels, Counter>::default();
        registry.register("http_requests", "HTTP requests answered, by route and status", requests.clone());
        let latency: Histograms<LatencyLabels> = Family::new_with_constructor(latency_buckets);
        registry.register("http_request_duration_seconds", "Time to answer an HTTP request, by route", latency.clone());
        let jobs = Family::<JobLabels, Counter>::default();
        registry.register("jobs", "Plans that ended, by planner and outcome", jobs.clone());
        let job_seconds: Histograms<JobLabels> = Family::new_with_constructor(job_buckets);
        registry.register("job_duration_seconds", "Time a plan ran, by planner and outcome", job_seconds.clone());
        let queued = Gauge::default();
        registry.register("queue_depth", "Plans waiting for a worker", queued.clone());
        let running = Gauge::default();
        registry.register("jobs_running", "Plans being planned now", running.clone());
        Arc::new(Telemetry { registry, requests, latency, jobs, job_seconds, queued, running })
    }

    pub fn request(&self, method: &str, route: &str, status: u16, took: Duration) {
        self.requests.get_or_create(&RouteLabels { method: method.into(), route: route.into(), status }).inc();
        self.latency.get_or_create(&LatencyLabels { method: method.into(), route: route.into() }).observe(took.as_secs_f64());
    }

    pub fn job(&self, planner: &str, outcome: &str, took: Duration) {
        let labels = JobLabels { planner: planner.into(), outcome: outcome.into() };
        self.jobs.get_or_create(&labels).inc();
        self.job_seconds.get_or_create(&labels).observe(took.as_secs_f64());
    }

    /// The metrics as text, with the gauges set to `queued` and `running` now.
    pub fn render(&self, queued: i64, running: i64) -> String {
        self.queued.set(queued);
        self.running.set(running);
        let mut text = String::new();
        prometheus_client::encoding::text::encode(&mut text, &self.registry).expect("writing to a String cannot fail");
        text
    }
}
