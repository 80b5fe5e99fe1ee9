//! The pages in `docs/performance/` are what `raystage-bench page` makes of the reports in
//! `docs/performance/data/` (scripts/performance.sh writes both): a page edited by hand, or
//! left behind when its report was measured again, fails here.

use std::path::Path;

#[test]
fn every_performance_page_is_made_from_its_report() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/performance");
    let mut pages = 0;
    for entry in std::fs::read_dir(dir.join("data")).expect("docs/performance/data holds the reports") {
        let report = entry.unwrap().path();
        if report.extension().is_none_or(|e| e != "jsonl") {
            continue;
        }
        let name = report.file_stem().unwrap().to_string_lossy().to_string();
        let made = raystage_bench::page::render(&std::fs::read_to_string(&report).unwrap()).unwrap_or_else(|e| panic!("{}: {e}", report.display()));
        let page = std::fs::read_to_string(dir.join(format!("{name}.md"))).unwrap_or_else(|e| panic!("docs/performance/{name}.md: {e}"));
        assert!(page == made, "docs/performance/{name}.md is not the page of data/{name}.jsonl: run `raystage-bench page docs/performance/data/{name}.jsonl > docs/performance/{name}.md`");
        pages += 1;
    }
    assert!(pages > 0, "no reports in docs/performance/data");
    // And no page without its report.
    for entry in std::fs::read_dir(&dir).unwrap() {
        let page = entry.unwrap().path();
        if page.extension().is_some_and(|e| e == "md") {
            let name = page.file_stem().unwrap().to_string_lossy().to_string();
            assert!(dir.join(format!("data/{name}.jsonl")).exists(), "docs/performance/{name}.md has no report in data/");
        }
    }
}
