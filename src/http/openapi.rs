//! The OpenAPI document: what is not a route (title, shared schemas, tags). The routes add
//! themselves in [`super::api`]. The committed copy lives in `openapi/openapi.json`.

use utoipa::OpenApi;

use super::error;

#[derive(OpenApi)]
#[openapi(
    info(title = "coverplan", description = "Coverage path planning for drones and farm vehicles: \
        store fields as missions, queue plans, fetch GeoJSON trajectories with length, time and energy. \
        Every error is an RFC 9457 problem (application/problem+json).", license(name = "MIT")),
    components(schemas(error::Problem, crate::planner::Stats, crate::planner::path::PieceKind)),
    tags((name = "missions"), (name = "plans"), (name = "planners"), (name = "vehicles"), (name = "health"))
)]
pub struct ApiDoc;

/// The document as the server serves it, pretty-printed.
pub fn document() -> String {
    super::api().into_openapi().to_pretty_json().expect("the OpenAPI document serialises") + "\n"
}
