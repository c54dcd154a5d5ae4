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
    let mut doc = super::api().into_openapi();
    complete(&mut doc);
    doc.to_pretty_json().expect("the OpenAPI document serialises") + "\n"
}

fn problem(description: &str) -> utoipa::openapi::Response {
    use utoipa::openapi::{ContentBuilder, Ref, ResponseBuilder};
    ResponseBuilder::new().description(description).content("application/problem+json", ContentBuilder::new().schema(Some(Ref::from_schema_name("Problem"))).build()).build()
}

/// What the middleware adds to the routes: the API key and its answers (401, 429) on every
/// tenant's route, and `Idempotency-Key` with its answers (409, 422) on every POST.
pub fn complete(doc: &mut utoipa::openapi::OpenApi) {
    use utoipa::openapi::path::{ParameterBuilder, ParameterIn};
    use utoipa::openapi::security::{HttpAuthScheme, HttpBuilder, SecurityRequirement, SecurityScheme};
    use utoipa::openapi::{ObjectBuilder, Required, Type};
    let components = doc.components.get_or_insert_with(Default::default);
    components.add_security_scheme(
        "api_key",
        SecurityScheme::Http(
            HttpBuilder::new()
                .scheme(HttpAuthScheme::Bearer)
                .description(Some("`Authorization: Bearer KEY`, a key from `coverplan keys create`; needed once the server has any key"))
                .build(),
        ),
    );
    for (_, item) in doc.paths.paths.iter_mut().filter(|(path, _)| super::auth::protected(path)) {
        for operation in [&mut item.get, &mut item.put, &mut item.post, &mut item.delete].into_iter().flatten() {
            operation.security = Some(vec![SecurityRequirement::new("api_key", Vec::<String>::new())]);
            let responses = &mut operation.responses.responses;
            responses.insert("401".into(), problem("no API key, or an unknown or revoked one (the server has keys)").into());
            responses.entry("429".into()).or_insert_with(|| problem("the key sends requests faster than the server allows (see `Retry-After`)").into());
        }
        if let Some(post) = &mut item.post {
            let key = ParameterBuilder::new()
                .name("Idempotency-Key")
                .parameter_in(ParameterIn::Header)
                .required(Required::False)
                .description(Some("Any 1 to 255 characters unique to this request: a retry with the same key and body gets the first answer again (kept a day)"))
                .schema(Some(ObjectBuilder::new().schema_type(Type::String).min_length(Some(1)).max_length(Some(255))))
                .build();
            post.parameters.get_or_insert_with(Vec::new).push(key.into());
            let responses = &mut post.responses.responses;
            responses.entry("409".into()).or_insert_with(|| problem("the first request with this Idempotency-Key is still being answered").into());
            responses.entry("422".into()).or_insert_with(|| problem("the Idempotency-Key was sent with another request").into());
            responses.entry("400".into()).or_insert_with(|| problem("a malformed Idempotency-Key").into());
        }
    }
}
