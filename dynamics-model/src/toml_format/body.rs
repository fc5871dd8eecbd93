//! The spatial inertia of a link from its TOML keys: mass and inertia about the centre of
//! mass or about a frame origin, a primitive solid (Exercise 8.1), a full 6×6 (Exercise 8.3),
//! or several bodies added in the link frame (Exercise 8.2).
//!
//! A body with mass `m`, centre of mass `c` and rotational inertia `I_c` about `c` (axes of
//! its body frame {b}) has, in {b},
//!
//! ```text
//! G_b = [[I_c + m(cᵀc·1₃ − c cᵀ), m[c]], [m[c]ᵀ, m·1₃]]        (I_o = I_c + m(cᵀc·1₃ − c cᵀ))
//! ```
//!
//! and in the link frame {i}, with `T_ib` the pose of {b} in {i} (`frame`),
//! `G_i = [Ad_{T_bi}]ᵀ G_b [Ad_{T_bi}]`. The bodies of one link are added: `G_i = Σ_k G_i,k`.

use super::pose::{array, pose, vector3};
use super::schema::{AboutSpec, BodySpec, ShapeSpec};
use crate::error::{Invalid, Subject};
use crate::inertia::{primitive, steiner, SpatialInertia};
use crate::lie::skew;
use crate::validate::{check_home, check_mass_and_inertia, check_spatial_inertia};
use nalgebra::{Matrix3, Matrix4, Matrix6, Vector3};

/// `G_i` of one body; every problem found is pushed to `errors` (then `None` is returned).
/// `prefix` is put before field names (`""` for the link's own keys, `body[k].` for a body).
pub(crate) fn body_inertia(
    subject: &Subject,
    prefix: &str,
    b: &BodySpec,
    errors: &mut Vec<Invalid>,
) -> Option<SpatialInertia> {
    let n_errors = errors.len();
    let f = |name: &str| format!("{prefix}{name}");
    let err = |name: &str, problem: String, fix: &str| {
        Invalid::new(subject.clone(), f(name), problem, fix)
    };

    let t_ib = match &b.frame {
        None => Matrix4::identity(),
        Some(v) => match pose(subject, &f("frame"), v) {
            Ok(t) => {
                if let Some(e) = check_home(subject.clone(), &f("frame"), &t) {
                    errors.push(e);
                }
                t
            }
            Err(e) => {
                errors.push(e);
                Matrix4::identity()
            }
        },
    };

    let g_b = if let Some(rows) = &b.spatial_inertia {
        for (key, given) in [
            ("mass", b.mass.is_some()),
            ("density", b.density.is_some()),
            ("shape", b.shape.is_some()),
            ("com", b.com.is_some()),
            ("inertia", b.inertia.is_some()),
            ("inertia_about", b.inertia_about.is_some()),
        ] {
            if given {
                errors.push(err(
                    key,
                    format!("`{key}` is given together with `spatial_inertia`"),
                    "the 6×6 spatial inertia already holds the mass, centre of mass and inertia: remove one of the two",
                ));
            }
        }
        spatial(subject, &f("spatial_inertia"), rows, errors)
    } else if let Some(shape) = &b.shape {
        for (key, given) in [
            ("inertia", b.inertia.is_some()),
            ("inertia_about", b.inertia_about.is_some()),
            ("com", b.com.is_some()),
        ] {
            if given {
                errors.push(err(
                    key,
                    format!("`{key}` is given together with `shape`"),
                    "a shape's inertia follows from its mass and size, and its centre of mass is its centre: remove the key, and place the shape with `frame`",
                ));
            }
        }
        solid(subject, prefix, shape, b.mass, b.density, errors)
    } else {
        point_and_inertia(subject, prefix, b, errors)
    };
    let g_b = g_b?;
    if errors.len() > n_errors {
        return None;
    }
    Some(if b.frame.is_some() {
        g_b.expressed_in(&t_ib)
    } else {
        g_b
    })
}

/// A full 6×6 given in {b}.
fn spatial(
    subject: &Subject,
    field: &str,
    rows: &[Vec<f64>],
    errors: &mut Vec<Invalid>,
) -> Option<SpatialInertia> {
    let fix = "give six rows of six numbers [[I, m[c]], [m[c]ᵀ, m·1₃]] (rows of the matrix)";
    if rows.len() != 6 || rows.iter().any(|r| r.len() != 6) {
        let sizes: Vec<usize> = rows.iter().map(Vec::len).collect();
        errors.push(Invalid::new(
            subject.clone(),
            field,
            format!("expected a 6×6 matrix (6 rows of 6 numbers), found rows of lengths {sizes:?}"),
            fix,
        ));
        return None;
    }
    let g = Matrix6::from_fn(|i, j| rows[i][j]);
    let problems = check_spatial_inertia(subject.clone(), field, &g);
    if !problems.is_empty() {
        errors.extend(problems);
        return None;
    }
    Some(SpatialInertia(g))
}

/// A primitive solid of given mass or density, centred at the origin of {b}.
fn solid(
    subject: &Subject,
    prefix: &str,
    shape: &ShapeSpec,
    mass: Option<f64>,
    density: Option<f64>,
    errors: &mut Vec<Invalid>,
) -> Option<SpatialInertia> {
    let field = format!("{prefix}shape");
    let (kind, dims): (&str, Vec<f64>) = match shape {
        ShapeSpec::Cuboid(v) => ("box", v.clone()),
        ShapeSpec::Cylinder(v) => ("cylinder", v.clone()),
        ShapeSpec::Sphere(r) => ("sphere", vec![*r]),
        ShapeSpec::Ellipsoid(v) => ("ellipsoid", v.clone()),
        ShapeSpec::Plate(v) => ("plate", v.clone()),
        ShapeSpec::Disc(r) => ("disc", vec![*r]),
    };
    let dim_field = format!("{field}.{kind}");
    let dims_ok = match kind {
        "box" | "ellipsoid" => array::<3>(subject, &dim_field, &dims).map(|_| ()),
        "cylinder" | "plate" => array::<2>(subject, &dim_field, &dims).map(|_| ()),
        _ => Ok(()),
    };
    if let Err(e) = dims_ok {
        errors.push(e);
        return None;
    }
    if let Some(x) = dims.iter().find(|x| !(x.is_finite() && **x > 0.0)) {
        errors.push(Invalid::new(
            subject.clone(),
            dim_field,
            format!("every size must be a positive length, found {x}"),
            "give the sizes in m, all > 0",
        ));
        return None;
    }
    let volume = match shape {
        ShapeSpec::Cuboid(_) => Some(primitive::cuboid_volume(dims[0], dims[1], dims[2])),
        ShapeSpec::Cylinder(_) => Some(primitive::cylinder_volume(dims[0], dims[1])),
        ShapeSpec::Sphere(_) => Some(primitive::sphere_volume(dims[0])),
        ShapeSpec::Ellipsoid(_) => Some(primitive::ellipsoid_volume(dims[0], dims[1], dims[2])),
        ShapeSpec::Plate(_) | ShapeSpec::Disc(_) => None,
    };
    let m = match (mass, density) {
        (Some(_), Some(_)) => {
            errors.push(Invalid::new(
                subject.clone(),
                format!("{prefix}density"),
                "both `mass` and `density` are given",
                "give one of them: the mass (kg), or the density (kg/m³, the mass is then density × volume)",
            ));
            return None;
        }
        (None, None) => {
            errors.push(Invalid::new(
                subject.clone(),
                format!("{prefix}mass"),
                format!("the {kind} has neither `mass` nor `density`"),
                "give `mass` (kg) or `density` (kg/m³)",
            ));
            return None;
        }
        (Some(m), None) => {
            if !(m.is_finite() && m >= 0.0) {
                errors.push(Invalid::new(
                    subject.clone(),
                    format!("{prefix}mass"),
                    format!("the mass must be ≥ 0, found {m} kg"),
                    "give a mass ≥ 0 in kg",
                ));
                return None;
            }
            m
        }
        (None, Some(rho)) => {
            let Some(volume) = volume else {
                errors.push(Invalid::new(
                    subject.clone(),
                    format!("{prefix}density"),
                    format!("a thin {kind} has no volume, so a density gives no mass"),
                    "give its `mass` instead",
                ));
                return None;
            };
            if !(rho.is_finite() && rho >= 0.0) {
                errors.push(Invalid::new(
                    subject.clone(),
                    format!("{prefix}density"),
                    format!("the density must be ≥ 0, found {rho} kg/m³"),
                    "give a density ≥ 0 in kg/m³",
                ));
                return None;
            }
            rho * volume
        }
    };
    let d = match shape {
        ShapeSpec::Cuboid(_) => primitive::cuboid(m, dims[0], dims[1], dims[2]),
        ShapeSpec::Cylinder(_) => primitive::cylinder(m, dims[0], dims[1]),
        ShapeSpec::Sphere(_) => primitive::sphere(m, dims[0]),
        ShapeSpec::Ellipsoid(_) => primitive::ellipsoid(m, dims[0], dims[1], dims[2]),
        ShapeSpec::Plate(_) => primitive::plate(m, dims[0], dims[1]),
        ShapeSpec::Disc(_) => primitive::disc(m, dims[0]),
    };
    Some(SpatialInertia::at_com(m, Matrix3::from_diagonal(&d)))
}

/// `mass` with `inertia` about the centre of mass (`com`, default the origin of {b}) or
/// about the origin of {b}.
fn point_and_inertia(
    subject: &Subject,
    prefix: &str,
    b: &BodySpec,
    errors: &mut Vec<Invalid>,
) -> Option<SpatialInertia> {
    let f = |name: &str| format!("{prefix}{name}");
    if b.density.is_some() {
        errors.push(Invalid::new(
            subject.clone(),
            f("density"),
            "`density` is given without a `shape`",
            "a density needs a shape to give a mass: add `shape = { box = [w, l, h] }` (or cylinder, sphere, ellipsoid), or give `mass` instead",
        ));
        return None;
    }
    let Some(m) = b.mass else {
        let (problem, fix) = if b.inertia.is_some() || b.com.is_some() || b.inertia_about.is_some()
        {
            (
                "an inertia or centre of mass is given without a `mass`",
                "add `mass` (kg)",
            )
        } else {
            (
                "no inertial data: none of `mass`, `shape`, `spatial_inertia` or bodies is given",
                "give `mass` and `inertia = [ixx, iyy, izz, ixy, ixz, iyz]` (or a `shape`, a `spatial_inertia`, or `[[joint.link.body]]`s); `mass = 0` for a massless link",
            )
        };
        errors.push(Invalid::new(subject.clone(), f("mass"), problem, fix));
        return None;
    };
    if !m.is_finite() || m < 0.0 {
        errors.push(Invalid::new(
            subject.clone(),
            f("mass"),
            format!("the mass must be finite and ≥ 0, found {m} kg"),
            "give a mass ≥ 0 in kg (0 for a massless link)",
        ));
        return None;
    }
    let c = match &b.com {
        Some(v) => match vector3(subject, &f("com"), v) {
            Ok(c) => c,
            Err(e) => {
                errors.push(e);
                return None;
            }
        },
        None => Vector3::zeros(),
    };
    let Some(inertia) = &b.inertia else {
        if b.inertia_about.is_some() {
            errors.push(Invalid::new(
                subject.clone(),
                f("inertia_about"),
                "`inertia_about` is given without `inertia`",
                "add `inertia = [ixx, iyy, izz, ixy, ixz, iyz]`, or remove `inertia_about`",
            ));
            return None;
        }
        if m == 0.0 {
            return Some(SpatialInertia::zero());
        }
        errors.push(Invalid::new(
            subject.clone(),
            f("inertia"),
            format!("a mass of {m} kg is given without its rotational inertia"),
            "add `inertia = [ixx, iyy, izz, ixy, ixz, iyz]` about the centre of mass (all zero for a point mass), or describe the body by a `shape`",
        ));
        return None;
    };
    let [ixx, iyy, izz, ixy, ixz, iyz] = match array::<6>(subject, &f("inertia"), inertia) {
        Ok(a) => a,
        Err(e) => {
            errors.push(e);
            return None;
        }
    };
    let i = Matrix3::new(ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz);
    // I_o (about the origin of {b}) and I_c (about the centre of mass).
    let (i_o, i_c) = match b.inertia_about.unwrap_or(AboutSpec::Com) {
        AboutSpec::Com => (i + steiner(m, &c), i),
        AboutSpec::Origin => (i, i - steiner(m, &c)),
    };
    let problems = check_mass_and_inertia(subject.clone(), &f("inertia"), m, &i_c);
    if !problems.is_empty() {
        errors.extend(problems);
        return None;
    }
    let mc = skew(&c) * m;
    let mut g = Matrix6::zeros();
    g.fixed_view_mut::<3, 3>(0, 0).copy_from(&i_o);
    g.fixed_view_mut::<3, 3>(0, 3).copy_from(&mc);
    g.fixed_view_mut::<3, 3>(3, 0).copy_from(&mc.transpose());
    g.fixed_view_mut::<3, 3>(3, 3)
        .copy_from(&(Matrix3::identity() * m));
    Some(SpatialInertia(g))
}
