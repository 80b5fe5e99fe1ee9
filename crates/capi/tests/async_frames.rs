//! Asynchronous frames through the C ABI (`rtRenderFrameAsync`, `rtFrameIsReady`,
//! `rtFrameWait`, `rtFrameCancel`, `rtFrameProgress`, `rtFrameRelease`), called in-process as a C
//! program would. Each test runs on its own thread, so each has its own context.

mod common;

use std::time::{Duration, Instant};

use common::{assert_error, assert_no_error, frame_buffer, handle, rgb, shader};
use raystage_capi::abi::*;

/// A Diffuse quad of `color` filling the view of a camera at z = 6 looking at the origin, and
/// that camera.
fn quad_scene(color: [f32; 3]) -> RTint {
    let diffuse = shader(c"Diffuse");
    rtBindShader(diffuse);
    let parameter = handle(c"diffuse");
    rtParameter3f(parameter, color[0], color[1], color[2]);
    let object = rtGenObjects(1);
    rtNewObject(object, RT_COMPILE);
    rtBegin(RT_QUADS);
    for (x, y) in [(-20.0, -20.0), (20.0, -20.0), (20.0, 20.0), (-20.0, 20.0)] {
        rtVertex3f(x, y, 0.0);
    }
    rtEnd();
    rtEndObject();
    rtInstantiateObject(object);
    rtLookAt(0.0, 0.0, 6.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0);
    assert_no_error();
    parameter
}

/// Whether `[r, g, b]` is mostly `channel` (0 red, 1 green, 2 blue).
fn mostly(pixel: [u8; 3], channel: usize) -> bool {
    pixel[channel] > 100 && (0..3).all(|c| c == channel || pixel[c] < pixel[channel] / 3)
}

#[test]
fn a_frame_completes_into_the_frame_buffer_with_monotonic_progress_and_frame_semantics() {
    let diffuse = quad_scene([1.0, 0.0, 0.0]);
    let (w, h) = (96, 64);
    let pixels = frame_buffer(w, h);
    let frame = rtRenderFrameAsync();
    assert_ne!(frame, 0);
    // Edits after the start belong to later frames: this one stays red.
    rtParameter3f(diffuse, 0.0, 1.0, 0.0);
    assert_no_error();

    let mut seen = vec![rtFrameProgress(frame)];
    while rtFrameProgress(frame) < 1.0 {
        seen.push(rtFrameProgress(frame));
        std::thread::sleep(Duration::from_millis(1));
    }
    seen.push(rtFrameProgress(frame));
    assert!(seen.windows(2).all(|p| p[0] <= p[1]), "progress went back: {seen:?}");
    assert!(seen.iter().all(|p| (0.0..=1.0).contains(p)), "{seen:?}");
    assert_eq!(seen.last(), Some(&1.0));
    // Rendered but not yet looked at: the image has not landed, so nothing raced the application.
    assert!(pixels.iter().all(|&b| b == 0), "the frame buffer changed before the frame was waited for");

    assert_eq!(rtFrameWait(frame), RT_NO_ERROR);
    assert_eq!(rtFrameIsReady(frame), 1);
    assert_eq!(rtFrameWait(frame), RT_NO_ERROR, "waiting again returns the same status");
    assert_eq!(rtFrameProgress(frame), 1.0);
    assert_no_error();
    assert!(mostly(rgb(&pixels, w, w / 2, h / 2), 0), "{:?} is not red", rgb(&pixels, w, w / 2, h / 2));

    // The edit shows in the next frame, synchronous or not.
    rtSwapBuffers();
    assert_no_error();
    assert!(mostly(rgb(&pixels, w, w / 2, h / 2), 1), "{:?} is not green", rgb(&pixels, w, w / 2, h / 2));
    rtFrameRelease(frame);
    assert_no_error();
}

#[test]
fn cancel_stops_the_work_and_wait_returns_at_once() {
    quad_scene([0.8, 0.8, 0.8]);
    let light = shader(c"PointLight");
    rtParameter3f(handle(c"position"), 0.0, 3.0, 3.0);
    rtParameter3f(handle(c"intensity"), 20.0, 20.0, 20.0);
    rtRenderMode(RT_PATH);
    rtRenderParameteri(RT_SAMPLES_PER_PIXEL, 1024);
    assert_no_error();
    assert_ne!(light, 0);
    let (w, h) = (512, 512);
    let pixels = frame_buffer(w, h);
    let frame = rtRenderFrameAsync();
    assert_no_error();

    // Let it do some work first, so that stopping it is seen.
    let started = Instant::now();
    while rtFrameProgress(frame) == 0.0 && started.elapsed() < Duration::from_secs(120) {
        std::thread::sleep(Duration::from_millis(5));
    }
    let before = rtFrameProgress(frame);
    assert!(before > 0.0 && before < 1.0, "progress {before} after {:?}", started.elapsed());
    rtFrameCancel(frame);
    let cancelled = Instant::now();
    assert_eq!(rtFrameWait(frame), RT_CANCELLED);
    let waited = cancelled.elapsed();
    // A whole band of rows took `started.elapsed()`; stopping must take far less than the rest.
    assert!(waited < Duration::from_secs(3), "rtFrameWait took {waited:?} after rtFrameCancel");
    assert_no_error();
    assert_eq!(rtFrameIsReady(frame), 1);

    let stopped = rtFrameProgress(frame);
    std::thread::sleep(Duration::from_millis(300));
    assert_eq!(rtFrameProgress(frame), stopped, "progress grew after the frame was cancelled");
    assert!(stopped < 1.0);
    assert!(pixels.iter().all(|&b| b == 0), "a cancelled frame wrote the frame buffer");
    rtFrameCancel(frame);
    assert_no_error();
    rtFrameRelease(frame);
    assert_no_error();
}

#[test]
fn release_stops_a_frame_in_flight_and_reset_stops_them_all() {
    quad_scene([0.8, 0.8, 0.8]);
    rtRenderMode(RT_PATH);
    rtRenderParameteri(RT_SAMPLES_PER_PIXEL, 1024);
    let pixels = frame_buffer(512, 512);
    let frame = rtRenderFrameAsync();
    let started = Instant::now();
    rtFrameRelease(frame);
    assert!(started.elapsed() < Duration::from_secs(3), "rtFrameRelease took {:?}", started.elapsed());
    assert_no_error();
    assert!(pixels.iter().all(|&b| b == 0), "a released frame wrote the frame buffer");

    // The context is free again, and a reset discards the frame in flight with everything else.
    assert_ne!(rtRenderFrameAsync(), 0);
    assert_no_error();
    let started = Instant::now();
    rtResetContext();
    assert!(started.elapsed() < Duration::from_secs(3), "rtResetContext took {:?}", started.elapsed());
    drop(pixels);

    // So does a thread's end, which drops its context.
    let started = Instant::now();
    std::thread::spawn(|| {
        quad_scene([0.8, 0.8, 0.8]);
        rtRenderMode(RT_PATH);
        rtRenderParameteri(RT_SAMPLES_PER_PIXEL, 1024);
        let pixels = frame_buffer(512, 512);
        assert_ne!(rtRenderFrameAsync(), 0);
        // The frame buffer must outlive the context, as rtFrameBuffer requires.
        std::mem::forget(pixels);
    })
    .join()
    .unwrap();
    assert!(started.elapsed() < Duration::from_secs(5), "the thread took {:?} to end", started.elapsed());
}

#[test]
fn one_frame_in_flight_per_context_and_bad_handles_are_errors() {
    assert_eq!(rtRenderFrameAsync(), 0);
    assert_error(RT_INVALID_OPERATION, "rtRenderFrameAsync: no frame buffer");

    quad_scene([0.0, 0.0, 1.0]);
    let (w, h) = (32, 32);
    let mut pixels = frame_buffer(w, h);
    let frame = rtRenderFrameAsync();
    assert_ne!(frame, 0);
    rtSwapBuffers();
    assert_error(RT_INVALID_OPERATION, &format!("rtSwapBuffers while frame {frame} is in flight"));
    assert_eq!(rtRenderFrameAsync(), 0);
    assert_error(RT_INVALID_OPERATION, &format!("rtRenderFrameAsync while frame {frame} is in flight"));
    unsafe { rtFrameBuffer(pixels.as_mut_ptr().cast(), w, h, RT_RGBA8) };
    assert_error(RT_INVALID_OPERATION, &format!("rtFrameBuffer while frame {frame} is in flight"));
    assert_eq!(rtFrameWait(frame), RT_NO_ERROR);
    assert!(mostly(rgb(&pixels, w, w / 2, h / 2), 2), "{:?} is not blue", rgb(&pixels, w, w / 2, h / 2));

    // Once waited for, the context renders again.
    rtSwapBuffers();
    let next = rtRenderFrameAsync();
    assert_no_error();
    assert!(next > frame);
    rtFrameRelease(next);
    rtFrameRelease(frame);
    assert_no_error();

    assert_eq!(rtFrameWait(0), RT_INVALID_VALUE);
    assert_error(RT_INVALID_VALUE, "rtFrameWait: frame handle 0 names no frame");
    assert_eq!(rtFrameWait(frame), RT_INVALID_VALUE);
    assert_error(RT_INVALID_VALUE, &format!("rtFrameWait: frame {frame} was released"));
    rtFrameRelease(frame);
    assert_error(RT_INVALID_VALUE, &format!("rtFrameRelease: frame {frame} was released"));
    // Handles are unique in the process: one never issued is told apart from a released one.
    let never = u32::MAX - 1;
    assert_eq!(rtFrameIsReady(never), 0);
    assert_error(RT_INVALID_VALUE, &format!("rtFrameIsReady: frame {never} does not exist"));
    assert_eq!(rtFrameProgress(never), 0.0);
    assert_error(RT_INVALID_VALUE, &format!("rtFrameProgress: frame {never} does not exist"));
    rtFrameCancel(u32::MAX);
    assert_error(RT_INVALID_VALUE, &format!("rtFrameCancel: frame {} does not exist", u32::MAX));

    // Handles belong to the context that made them.
    let other = std::thread::spawn(move || {
        let status = rtFrameWait(next);
        (status, common::error())
    });
    let (status, (code, message)) = other.join().unwrap();
    assert_eq!((status, code), (RT_INVALID_VALUE, RT_INVALID_VALUE));
    assert!(message.contains(&format!("frame {next} was released or belongs to another thread's context")), "{message}");
}

#[test]
fn frames_in_flight_on_two_contexts_render_their_own_scenes() {
    // Each thread has its own context; the barrier holds both frames in flight at once.
    let barrier = std::sync::Arc::new(std::sync::Barrier::new(2));
    let threads: Vec<_> = (0..2)
        .map(|channel| {
            let barrier = barrier.clone();
            std::thread::spawn(move || {
                let mut color = [0.0; 3];
                color[channel] = 1.0;
                quad_scene(color);
                rtRenderParameteri(RT_SAMPLES_PER_PIXEL, 16);
                let (w, h) = (160, 120);
                let pixels = frame_buffer(w, h);
                let frame = rtRenderFrameAsync();
                assert_ne!(frame, 0);
                barrier.wait();
                assert_eq!(rtFrameWait(frame), RT_NO_ERROR);
                assert_no_error();
                let pixel = rgb(&pixels, w, w / 2, h / 2);
                assert!(mostly(pixel, channel), "context {channel}'s frame is {pixel:?}");
                rtFrameRelease(frame);
                assert_no_error();
                frame
            })
        })
        .collect();
    let handles: Vec<RTuint> = threads.into_iter().map(|t| t.join().unwrap()).collect();
    assert_ne!(handles[0], handles[1], "handles are unique across contexts");
}
