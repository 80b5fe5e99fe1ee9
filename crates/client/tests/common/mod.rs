//! A real server for the tests, in-process.

/// A server on a free loopback port with the Cornell room as scene 1, and its URL; it runs
/// until the runtime is dropped.
pub fn server() -> (tokio::runtime::Runtime, String) {
    let runtime = tokio::runtime::Builder::new_multi_thread().worker_threads(2).enable_all().build().unwrap();
    let state = raystage_server::AppState::new(raystage_server::Config::default());
    let demo = raystage_demo::animated::Demo::from_name("cornell").unwrap();
    state.add_scene(demo.scene(0).unwrap(), "demo:cornell").unwrap();
    let listener = runtime.block_on(tokio::net::TcpListener::bind("127.0.0.1:0")).unwrap();
    let url = format!("http://{}", listener.local_addr().unwrap());
    runtime.spawn(raystage_server::serve(listener, state, std::future::pending()));
    (runtime, url)
}
