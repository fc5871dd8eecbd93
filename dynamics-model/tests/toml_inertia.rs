//! The inertia forms of the TOML format against the chapter-8 exercises of
//! tests/data/seed-cases.json: primitives (8.1) by mass and by density, the dumbbell (8.2)
//! as three bodies, and the change of frame (8.3) written four ways.

use dynamics_model::load::{from_str, Format};
use dynamics_model::LoadOptions;
use nalgebra::Matrix6;
use serde_json::Value;

fn seed() -> Value {
    let path = format!(
        "{}/../tests/data/seed-cases.json",
        env!("CARGO_MANIFEST_DIR")
    );
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap()
}

fn rows(v: &Value) -> Vec<Vec<f64>> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|r| r.as_array().unwrap().iter().map(f).collect())
        .collect()
}

/// A one-joint robot whose link has the inertial keys `body`; returns `G_1`.
fn g_of(body: &str) -> Matrix6<f64> {
    let text = format!(
        "name = \"one\"\n\n[[joint]]\nname = \"j\"\ntype = \"revolute\"\nscrew = [0, 0, 1, 0, 0, 0]\n\n[joint.link]\nname = \"l\"\nhome = {{ xyz = [0, 0, 0] }}\n{body}\n"
    );
    let robot = from_str(&text, Format::Toml, "test.toml", &LoadOptions::default())
        .unwrap_or_else(|e| panic!("{e}\n{text}"));
    robot.links[0].inertia.0
}

/// ‖a − b‖∞ ≤ 1e-12·max(1, ‖b‖∞); returns the error.
fn assert_close(what: &str, a: &Matrix6<f64>, b: &Matrix6<f64>) -> f64 {
    let err = (a - b).amax();
    assert!(
        err <= 1e-12 * b.amax().max(1.0),
        "{what}: error {err:e}\n{a}\n{b}"
    );
    err
}

fn diag(m: f64, i: [f64; 3]) -> Matrix6<f64> {
    Matrix6::from_diagonal(&nalgebra::Vector6::new(i[0], i[1], i[2], m, m, m))
}

fn expected_diag(case: &Value) -> [f64; 3] {
    let i = rows(&case["I_expected"]);
    // Off-diagonal entries are zero in every case.
    for (r, row) in i.iter().enumerate() {
        for (c, x) in row.iter().enumerate() {
            assert!(r == c || *x == 0.0);
        }
    }
    [i[0][0], i[1][1], i[2][2]]
}

#[test]
fn exercise_8_1_primitives_by_mass_and_by_density() {
    let s = seed();
    let cases = &s["exercises"]["ex8_1_inertia"];
    let pi = std::f64::consts::PI;
    // (case, shape, volume or None for thin shapes)
    let b = &cases["box"];
    let (w, l, h) = (f(&b["w"]), f(&b["l"]), f(&b["h"]));
    let c = &cases["solid_cylinder"];
    let (r, hc) = (f(&c["r"]), f(&c["h"]));
    let e = &cases["ellipsoid"];
    let (ea, eb, ec) = (f(&e["a"]), f(&e["b"]), f(&e["c"]));
    let sp = &cases["solid_sphere"];
    let rs = f(&sp["r"]);
    let p = &cases["thin_plate"];
    let d = &cases["thin_disc"];
    let shapes = [
        (
            b,
            format!("{{ box = [{w:?}, {l:?}, {h:?}] }}"),
            Some(w * l * h),
        ),
        (
            c,
            format!("{{ cylinder = [{r:?}, {hc:?}] }}"),
            Some(pi * r * r * hc),
        ),
        (
            e,
            format!("{{ ellipsoid = [{ea:?}, {eb:?}, {ec:?}] }}"),
            Some(4.0 / 3.0 * pi * ea * eb * ec),
        ),
        (
            sp,
            format!("{{ sphere = {rs:?} }}"),
            Some(4.0 / 3.0 * pi * rs.powi(3)),
        ),
        (
            p,
            format!("{{ plate = [{:?}, {:?}] }}", f(&p["w"]), f(&p["l"])),
            None,
        ),
        (d, format!("{{ disc = {:?} }}", f(&d["r"])), None),
    ];
    let mut worst: f64 = 0.0;
    for (case, shape, volume) in shapes {
        let m = f(&case["mass"]);
        let want = diag(m, expected_diag(case));
        let by_mass = g_of(&format!("shape = {shape}\nmass = {m:?}"));
        worst = worst.max(assert_close(&shape, &by_mass, &want));
        if let Some(v) = volume {
            let by_density = g_of(&format!("shape = {shape}\ndensity = {:?}", m / v));
            worst = worst.max(assert_close(&shape, &by_density, &want));
        }
    }
    eprintln!("8.1 worst error {worst:e}");
}

#[test]
fn exercise_8_2_dumbbell_from_three_bodies() {
    let s = seed();
    let d = &s["exercises"]["ex8_2_dumbbell"];
    let p = &d["parameters"];
    let (rho, big_r, r, len) = (
        f(&p["density"]),
        f(&p["sphere_radius"]),
        f(&p["handle_radius"]),
        f(&p["handle_length"]),
    );
    let offset = len / 2.0 + big_r;
    let text = format!(
        r#"
[[joint.link.body]]
name = "handle"
shape = {{ cylinder = [{r:?}, {len:?}] }}
density = {rho:?}

[[joint.link.body]]
name = "top"
shape = {{ sphere = {big_r:?} }}
density = {rho:?}
frame = {{ xyz = [0, 0, {offset:?}] }}

[[joint.link.body]]
name = "bottom"
shape = {{ sphere = {big_r:?} }}
density = {rho:?}
frame = {{ xyz = [0, 0, {:?}] }}
"#,
        -offset
    );
    let g = g_of(&text);
    let want: Vec<f64> = d["G_expected_diag"]
        .as_array()
        .unwrap()
        .iter()
        .map(f)
        .collect();
    let want = Matrix6::from_diagonal(&nalgebra::Vector6::from_column_slice(&want));
    let err = assert_close("dumbbell", &g, &want);
    // The brief's numbers, too.
    assert!((g[(0, 0)] - 2.7710732160254143).abs() < 1e-12);
    assert!((g[(2, 2)] - 0.25170440340561434).abs() < 1e-12);
    assert!((g[(3, 3)] - 64.71680866394975).abs() < 1e-12);
    eprintln!("8.2 error {err:e}");
}

/// The numbers of Exercise 8.3.
struct Ex83 {
    i_b: Vec<Vec<f64>>,
    m: f64,
    r_ba: Vec<Vec<f64>>,
    p_ab: Vec<f64>,
    i_a: Vec<Vec<f64>>,
    g_a: Matrix6<f64>,
}

fn ex8_3() -> Ex83 {
    let s = seed();
    let x = &s["exercises"]["ex8_3_spatial_inertia_transform"];
    let g_a = rows(&x["G_a_expected"]);
    Ex83 {
        i_b: rows(&x["I_b"]),
        m: f(&x["mass"]),
        r_ba: rows(&x["R_ba"]),
        p_ab: x["p_ab"].as_array().unwrap().iter().map(f).collect(),
        i_a: rows(&x["I_a_expected"]),
        g_a: Matrix6::from_fn(|i, j| g_a[i][j]),
    }
}

fn inertia6(i: &[Vec<f64>]) -> String {
    format!(
        "[{:?}, {:?}, {:?}, {:?}, {:?}, {:?}]",
        i[0][0], i[1][1], i[2][2], i[0][1], i[0][2], i[1][2]
    )
}

/// The pose of {b} in {a}, `T_ab = [[R_baᵀ, p_ab], [0, 1]]`, as a TOML 4×4.
fn t_ab(r_ba: &[Vec<f64>], p_ab: &[f64]) -> String {
    let row = |i: usize| {
        format!(
            "[{:?}, {:?}, {:?}, {:?}]",
            r_ba[0][i], r_ba[1][i], r_ba[2][i], p_ab[i]
        )
    };
    format!("[{}, {}, {}, [0, 0, 0, 1]]", row(0), row(1), row(2))
}

#[test]
fn exercise_8_3_inertia_about_the_com_in_a_rotated_offset_frame() {
    let Ex83 {
        i_b,
        m,
        r_ba,
        p_ab,
        g_a,
        ..
    } = ex8_3();
    let g = g_of(&format!(
        "mass = {m:?}\ninertia = {}\nframe = {}",
        inertia6(&i_b),
        t_ab(&r_ba, &p_ab)
    ));
    assert_close("8.3 mass + inertia + frame", &g, &g_a);
}

#[test]
fn exercise_8_3_spatial_inertia_in_another_frame() {
    let Ex83 {
        i_b,
        m,
        r_ba,
        p_ab,
        g_a,
        ..
    } = ex8_3();
    let mut g_b = format!(
        "[[{:?}, {:?}, {:?}, 0, 0, 0]",
        i_b[0][0], i_b[0][1], i_b[0][2]
    );
    for r in 1..3 {
        g_b += &format!(
            ", [{:?}, {:?}, {:?}, 0, 0, 0]",
            i_b[r][0], i_b[r][1], i_b[r][2]
        );
    }
    g_b += &format!(", [0, 0, 0, {m:?}, 0, 0], [0, 0, 0, 0, {m:?}, 0], [0, 0, 0, 0, 0, {m:?}]]");
    let g = g_of(&format!(
        "spatial_inertia = {g_b}\nframe = {}",
        t_ab(&r_ba, &p_ab)
    ));
    assert_close("8.3 spatial_inertia + frame", &g, &g_a);
    // And the expected G_a itself, in {a}, is taken as it is.
    let rows: Vec<String> = (0..6)
        .map(|i| {
            let r: Vec<String> = (0..6).map(|j| format!("{:?}", g_a[(i, j)])).collect();
            format!("[{}]", r.join(", "))
        })
        .collect();
    let g = g_of(&format!("spatial_inertia = [{}]", rows.join(", ")));
    assert_eq!(g, g_a);
}

#[test]
fn exercise_8_3_inertia_about_a_point_other_than_the_com() {
    // I_a about the origin of {a}, with the centre of mass p_ab in {a}: exactly G_a.
    let Ex83 {
        m, p_ab, i_a, g_a, ..
    } = ex8_3();
    let g = g_of(&format!(
        "mass = {m:?}\ncom = [{:?}, {:?}, {:?}]\ninertia = {}\ninertia_about = \"origin\"",
        p_ab[0],
        p_ab[1],
        p_ab[2],
        inertia6(&i_a)
    ));
    assert_close("8.3 inertia_about origin", &g, &g_a);
}

#[test]
fn steiner_case_inertia_about_an_offset_com() {
    let s = seed();
    let x = &s["exercises"]["ex8_3_spatial_inertia_transform"];
    let st = &x["steiner_R_identity"];
    let q: Vec<f64> = st["q"].as_array().unwrap().iter().map(f).collect();
    let want = rows(&st["I_a_expected"]);
    // The COM frame {b} sits at p_ab = −q in {a} (seed-cases: c = p_ab = −R_baᵀ p_ba).
    let g = g_of(&format!(
        "mass = {:?}\ninertia = {}\ncom = [{:?}, {:?}, {:?}]",
        f(&x["mass"]),
        inertia6(&rows(&x["I_b"])),
        -q[0],
        -q[1],
        -q[2]
    ));
    for i in 0..3 {
        for j in 0..3 {
            assert!(
                (g[(i, j)] - want[i][j]).abs() < 1e-14,
                "{i},{j}: {}",
                g[(i, j)]
            );
        }
    }
}
