//! The crates' layers, as the C library links them: a C program that joins an MPI job
//! (`rtInitMPI`, the `mpi` feature) links the cluster and the service, never the HTTP server
//! and its web stack; and neither the service nor the cluster depends on a crate above it
//! (docs/design/architecture.md, "Crates"). Read from `cargo tree`, so a dependency added to a
//! manifest fails here before anyone links it.

use std::process::Command;

/// The packages `package` links with `features` (its normal dependencies, recursively), as
/// `cargo tree` lists them; `None`, after saying why, where cargo cannot be run.
fn linked(package: &str, features: &[&str]) -> Option<Vec<String>> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let mut command = Command::new(cargo);
    command.args(["tree", "--offline", "-e", "normal", "--prefix", "none", "--format", "{p}", "-p", package]);
    if !features.is_empty() {
        command.args(["--features", &features.join(",")]);
    }
    let output = match command.current_dir(env!("CARGO_MANIFEST_DIR")).output() {
        Ok(output) => output,
        Err(e) => {
            eprintln!("skipped: cannot run cargo ({e})");
            return None;
        }
    };
    assert!(output.status.success(), "cargo tree -p {package} failed: {}", String::from_utf8_lossy(&output.stderr));
    // Lines are `name vVERSION (path)`: the name is the first word.
    Some(String::from_utf8_lossy(&output.stdout).lines().filter_map(|line| line.split_whitespace().next()).map(String::from).collect())
}

/// Asserts that `package` with `features` links none of `above`, and does link each of
/// `below` (so that the check reads the tree it means to).
fn check(package: &str, features: &[&str], below: &[&str], above: &[&str]) {
    let Some(linked) = linked(package, features) else { return };
    for name in below {
        assert!(linked.iter().any(|p| p == name), "{package} {features:?} should link {name}; it links {linked:?}");
    }
    for name in above {
        assert!(!linked.iter().any(|p| p == name), "{package} {features:?} links {name}, a layer above it");
    }
}

/// The web stack the HTTP server brings.
const HTTP: [&str; 4] = ["raystage-server", "axum", "hyper", "tokio-tungstenite"];

#[test]
fn a_c_program_in_an_mpi_job_links_no_http() {
    check("raystage-capi", &["mpi"], &["raystage-cluster", "raystage-service", "mpi"], &HTTP);
}

#[test]
fn a_c_program_alone_links_neither_the_service_nor_the_cluster() {
    check("raystage-capi", &[], &["raystage-render"], &["raystage-cluster", "raystage-service", "mpi", "raystage-server", "axum"]);
}

#[test]
fn the_service_and_the_cluster_depend_on_nothing_above_them() {
    check("raystage-service", &[], &["raystage-scene", "raystage-render"], &["raystage-cluster", "raystage-client", "mpi"].iter().chain(&HTTP).copied().collect::<Vec<_>>());
    check("raystage-cluster", &["mpi"], &["raystage-service", "mpi"], &["raystage-client"].iter().chain(&HTTP).copied().collect::<Vec<_>>());
}
