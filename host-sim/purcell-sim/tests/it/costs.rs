//! Issue 37: `report.json` gives both costs of every gait, `costs.effort` the cost `solve`
//! minimised (to the bit) and `costs.power` the power its controls dissipate, recomputed here
//! from `trajectory.csv`'s controls alone: the shapes integrated from `ᾱ`, each link's
//! dissipation from its own velocity (`purcell_solver::testkit::dissipated`).

use crate::common;

use common::*;
use nalgebra::Vector2;
use purcell_core::Swimmer;
use purcell_solver::testkit::dissipated;

#[test]
fn the_report_s_power_cost_is_the_dissipation_of_the_trajectory_s_controls() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let o = Solve::quick().no_plots().out(&out).run();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let r = report(&out);
    assert_eq!(r["costs"]["effort"], r["cost"]);
    for x in r["extremals"].as_array().unwrap() {
        assert_eq!(x["costs"]["effort"], x["cost"]);
        assert!(x["costs"]["power"].as_f64().unwrap() > 0.0);
    }
    let p = &r["problem"];
    let f = |v: &serde_json::Value| v.as_f64().unwrap();
    let links = [0, 1, 2].map(|i| f(&p["links"][i]));
    let sw = Swimmer::new(links, f(&p["drag"]), f(&p["ratio"])).unwrap();
    let h = f(&p["step"]);
    let csv = std::fs::read_to_string(out.join("trajectory.csv")).unwrap();
    let mut alpha = Vector2::new(f(&p["alpha0"][0]), f(&p["alpha0"][1]));
    let mut sum = 0.0;
    // Rows k = 0 … N; the last one's control is 0.
    for line in csv.lines().skip(1) {
        let cells: Vec<f64> = line.split(',').map(|c| c.parse().unwrap()).collect();
        let u = Vector2::new(cells[4], cells[5]);
        sum += dissipated(&sw, &alpha, &u);
        alpha += u * h;
    }
    let power = f(&r["costs"]["power"]);
    let recomputed = 0.5 * h * sum;
    assert!(
        (recomputed - power).abs() <= 1e-12 * power,
        "report {power}, recomputed {recomputed}"
    );
}

/// The schemas name the costs of the core's one table (`purcell_core::for_each_cost!`): the
/// enum of `problem.cost` in both reports, and `costs`' properties and required keys.
#[test]
fn the_schemas_name_the_costs_of_the_core_s_table() {
    let names: Vec<&str> = purcell_core::Cost::ALL.map(|c| c.name()).to_vec();
    let schema = |name: &str| -> serde_json::Value {
        let path = format!("{}/../../docs/schemas/{name}", env!("CARGO_MANIFEST_DIR"));
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
    };
    let strings = |v: &serde_json::Value| -> Vec<String> {
        let list = v.as_array().unwrap().iter();
        list.map(|s| s.as_str().unwrap().to_string()).collect()
    };
    for file in ["solve-report.schema.json", "sweep-report.schema.json"] {
        let s = schema(file);
        let cost = &s["properties"]["problem"]["properties"]["cost"]["enum"];
        assert_eq!(strings(cost), names, "{file}: problem.cost");
    }
    let costs = &schema("solve-report.schema.json")["$defs"]["costs"];
    let mut properties: Vec<&str> = costs["properties"]
        .as_object()
        .unwrap()
        .keys()
        .map(String::as_str)
        .collect();
    let mut sorted = names.clone();
    properties.sort_unstable();
    sorted.sort_unstable();
    assert_eq!(properties, sorted, "costs' properties");
    assert_eq!(strings(&costs["required"]), names, "costs' required");
}
