//! `/scenes/{scene}/renders` and `/renders/{id}`: frames rendered as jobs (see
//! [`raystage_service::Jobs`]), started, polled, fetched and deleted over HTTP.

use std::sync::Arc;

use axum::Json;
use axum::extract::{Path, State};
use axum::http::{StatusCode, header};
use axum::response::{IntoResponse, Response};
use raystage_service::{AppState, Error, RenderJobInfo};

use crate::error::{ApiResult, ErrorBody};
use crate::extract::{Params, Target};
use crate::render::{FrameQuery, render_png};

/// Starts rendering a frame of the scene (the query as `frame.png` takes it) and answers at
/// once, 202 with the job; `Location` names it. At most `max_render_jobs` jobs are held at once,
/// finished ones included until deleted or expired; past it the oldest finished job is dropped,
/// and only if every job still renders is the new one refused (413 naming the limit, as for
/// `max_scenes`: the client holds them and must delete some, so it is not the server failing,
/// which a 5xx would say).
#[utoipa::path(post, path = "/scenes/{scene}/renders", tag = "frames",
    params(("scene" = u32, Path, description = "The scene's id"), FrameQuery),
    responses(
        (status = 202, description = "Started", body = RenderJobInfo),
        (status = 400, description = "Malformed request: the error names the field", body = ErrorBody),
        (status = 404, description = "No such scene, resource or route", body = ErrorBody),
        (status = 422, description = "A value is not acceptable: the error names the field", body = ErrorBody),
        (status = 413, description = "As many render jobs as the server holds", body = ErrorBody),
    ))]
pub(crate) async fn start(State(state): State<AppState>, target: Target, Params(query): Params<FrameQuery>) -> ApiResult<Response> {
    let limits = state.config().limits;
    let frame = query.check(&limits)?;
    let job = state.jobs().add(target.scene.id, frame.render.width, frame.render.height, &limits)?;
    // The job takes its turns as the connection that made it: a backlog of jobs is one client's.
    let (runner, slot, client) = (Arc::clone(&job), target.scene, target.client);
    // Frame semantics: the job renders the scene as it is now, whatever is edited meanwhile.
    let _ = slot.follow_clock(&state).await;
    let snapshot = slot.snapshot().await;
    let task = tokio::spawn(async move {
        let outcome = render_png(&state, &slot, client, Some(snapshot), frame, runner.rows()).await;
        state.jobs().finish(&runner, outcome, &state.config().limits);
    });
    job.set_task(task.abort_handle());
    let location = format!("/renders/{}", job.id());
    Ok((StatusCode::ACCEPTED, [(header::LOCATION, location)], Json(job.info())).into_response())
}

/// Every render job, by id.
#[utoipa::path(get, path = "/renders", tag = "frames", responses((status = 200, description = "Success", body = [RenderJobInfo])))]
pub(crate) async fn list(State(state): State<AppState>) -> Json<Vec<RenderJobInfo>> {
    Json(state.jobs().list(&state.config().limits).iter().map(|j| j.info()).collect())
}

/// A render job: its status and progress, and once done its statistics.
#[utoipa::path(get, path = "/renders/{id}", tag = "frames",
    params(("id" = u32, Path, description = "The job's id")),
    responses(
        (status = 200, description = "Success", body = RenderJobInfo),
        (status = 404, description = "No such job", body = ErrorBody),
    ))]
pub(crate) async fn get(State(state): State<AppState>, Path(id): Path<String>) -> ApiResult<Json<RenderJobInfo>> {
    Ok(Json(state.jobs().get(&id, &state.config().limits)?.info()))
}

/// A finished job's image, as PNG (409 while it renders, or if it failed).
#[utoipa::path(get, path = "/renders/{id}/image.png", tag = "frames",
    params(("id" = u32, Path, description = "The job's id")),
    responses(
        (status = 200, description = "The frame", content_type = "image/png", body = raystage_service::model::Binary),
        (status = 404, description = "No such job", body = ErrorBody),
        (status = 409, description = "Not done: still rendering, or failed", body = ErrorBody),
    ))]
pub(crate) async fn image(State(state): State<AppState>, Path(id): Path<String>) -> ApiResult<Response> {
    match state.jobs().get(&id, &state.config().limits)?.image() {
        Some(Ok(png)) => Ok(([(header::CONTENT_TYPE, "image/png"), (header::CACHE_CONTROL, "no-store")], png).into_response()),
        Some(Err(why)) => Err(Error::conflict(format!("render job {id} failed: {why}")).into()),
        None => Err(Error::conflict(format!("render job {id} is still rendering: poll /renders/{id} until its status is done")).into()),
    }
}

/// Deletes a job, stopping its render if it is still running (its turn and memory go to the
/// next render once the work has stopped).
#[utoipa::path(delete, path = "/renders/{id}", tag = "frames",
    params(("id" = u32, Path, description = "The job's id")),
    responses(
        (status = 204, description = "Deleted"),
        (status = 404, description = "No such job", body = ErrorBody),
    ))]
pub(crate) async fn delete(State(state): State<AppState>, Path(id): Path<String>) -> ApiResult<StatusCode> {
    state.jobs().delete(&id, &state.config().limits)?;
    Ok(StatusCode::NO_CONTENT)
}
