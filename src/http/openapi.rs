//! The OpenAPI document of every route. The committed copy lives in `openapi/openapi.json`.

use utoipa::OpenApi;

use super::{error, health, missions, planners, plans, ui, vehicles};

#[derive(OpenApi)]
#[openapi(
    info(title = "coverplan", description = "Coverage path planning for drones and farm vehicles: \
        store fields as missions, queue plans, fetch GeoJSON trajectories with length, time and energy. \
        Every error is an RFC 9457 problem (application/problem+json).", license(name = "MIT")),
    paths(
        health::healthz, health::readyz,
        missions::create, missions::list, missions::get, missions::update, missions::delete,
        plans::create, plans::list, plans::get, plans::trajectory, plans::cancel,
        planners::list,
        planners::cameras,
        ui::config,
        vehicles::list, vehicles::get, vehicles::create, vehicles::update, vehicles::delete, vehicles::estimate,
    ),
    components(schemas(error::Problem, crate::planner::Stats, crate::planner::path::PieceKind)),
    tags((name = "missions"), (name = "plans"), (name = "planners"), (name = "vehicles"), (name = "health"))
)]
pub struct ApiDoc;

/// The document as the server serves it, pretty-printed.
pub fn document() -> String {
    ApiDoc::openapi().to_pretty_json().expect("the OpenAPI document serialises") + "\n"
}
