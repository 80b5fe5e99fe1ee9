//! `/scenes/{scene}/commands`: many edits in one request, all or nothing.

use axum::Json;
use axum::extract::State;
use raystage_service::AppState;
use raystage_service::model::{Commands, CommandsResult};

use crate::commands::parse_commands;
use crate::error::{ApiResult, ErrorBody};
use crate::extract::{RawBody, Target, parse_body};

/// Runs a batch of edits in order. Every command is checked first, against the scene as the
/// commands before it will leave it; if any fails, none is applied, and the error names it
/// (`commands[3].add_instance.transform`). A command can refer to a resource an earlier one
/// created by the `label` it gave it.
#[utoipa::path(post, path = "/scenes/{scene}/commands", tag = "commands",
    params(("scene" = u32, Path, description = "The scene's id")),
    request_body = Commands,
    responses(
        (status = 200, description = "Success", body = CommandsResult),
        (status = 400, description = "Malformed request: the error names the field", body = ErrorBody),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
        (status = 413, description = "Larger than the server allows", body = ErrorBody),
        (status = 422, description = "A value is not acceptable: the error names the field", body = ErrorBody),
    ))]
pub(crate) async fn run(State(state): State<AppState>, target: Target, RawBody(body): RawBody) -> ApiResult<Json<CommandsResult>> {
    let max = state.config().limits.max_commands;
    let body = parse_body(body, move |bytes| parse_commands(bytes, max, false).map(|(commands, _)| commands)).await?;
    let (results, version) = target.scene.commands(&state, body.commands, true).await?;
    Ok(Json(CommandsResult { version, results }))
}
