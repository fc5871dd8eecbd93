//! The expansion of robots with mimic joints on seeded random trees: the graph's inputs are
//! the coordinates only, its outputs equal the expansion of the same robot with every joint
//! independent, evaluated at `θ = J x + o` and projected by `J` in numbers here, forward
//! dynamics takes the LDLᵀ route and inverts inverse dynamics, and `M` keeps exact zeros
//! between coordinates on different branches. (Agreement with the reference implementation
//! and with Pinocchio is checked in the `dynamics-tests` crate.)

use super::*;
use dynamics_model::random::{random_mimics, random_tree, Rng, TreeSpec};

fn eval(d: &Dynamics, roots: &[ExprId], q: &[f64], v: &[f64], a: &[f64], tau: &[f64]) -> Vec<f64> {
    d.graph.eval(roots, &|x: Input| {
        let i = x.index as usize;
        match x.group {
            Q => q[i],
            QD => v[i],
            QDD => a[i],
            _ => tau[i],
        }
    })
}

fn close(what: &str, x: &[f64], y: &[f64]) {
    let scale = y.iter().fold(1.0f64, |m, b| m.max(b.abs()));
    let err = x
        .iter()
        .zip(y)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(
        x.len() == y.len() && err <= 1e-10 * scale,
        "{what}: error {err:e}"
    );
}

fn robots() -> Vec<dynamics_model::Robot> {
    (0..16u64)
        .map(|seed| {
            let spec = TreeSpec {
                dof: 2 + (seed as usize * 5) % 11,
                prismatic: 0.25,
                branching: 0.4,
                floating: seed % 2 == 1,
            };
            random_mimics(random_tree(seed, spec), seed, 0.5)
        })
        .filter(|r| r.has_mimic())
        .collect()
}

#[test]
fn coupled_expansion_is_the_physical_one_projected() {
    let robots = robots();
    assert!(
        robots.len() >= 12,
        "{} robots with mimic joints",
        robots.len()
    );
    for (k, r) in robots.iter().enumerate() {
        let d = expand(r);
        let (nq, nv, n) = (r.nq(), r.nv(), r.n_coordinates());
        assert_eq!((d.dof, d.nq, d.nv), (n, nq, nv));
        assert_eq!(d.forward_route, ForwardRoute::Ldlt, "robot {k}");
        // Only the coordinates are inputs (and the tip wrench's six).
        for x in d.graph.inputs() {
            let len = match x.group {
                Q => nq,
                super::task_space::F_TIP => 6,
                _ => nv,
            };
            assert!((x.index as usize) < len, "robot {k}: input {x}");
        }
        let mut physical = r.clone();
        for j in &mut physical.joints {
            j.mimic = None;
        }
        let p = expand(&physical);
        let (oq, ov) = (nq - n, nv - n);
        let couplings = r.couplings();
        let mut rng = Rng::new(k as u64);
        let mut q: Vec<f64> = (0..nq).map(|_| rng.uniform(-2.0, 2.0)).collect();
        if r.base.floating {
            let norm = q[3..7].iter().map(|x| x * x).sum::<f64>().sqrt();
            q[3..7].iter_mut().for_each(|x| *x /= norm);
        }
        let v: Vec<f64> = (0..nv).map(|_| rng.uniform(-1.5, 1.5)).collect();
        let a: Vec<f64> = (0..nv).map(|_| rng.uniform(-1.5, 1.5)).collect();
        // θ = J x + o, ν_phys = J ν; J has one entry per physical row.
        let mut q_p = q[..oq].to_vec();
        q_p.extend(
            couplings
                .iter()
                .map(|c| c.multiplier * q[oq + c.coordinate] + c.offset),
        );
        let rate = |x: &[f64]| -> Vec<f64> {
            let mut y = x[..ov].to_vec();
            y.extend(
                couplings
                    .iter()
                    .map(|c| c.multiplier * x[ov + c.coordinate]),
            );
            y
        };
        let (v_p, a_p) = (rate(&v), rate(&a));
        let nv_p = physical.nv();
        let jt = |f: &[f64]| -> Vec<f64> {
            let mut y = f[..ov].to_vec();
            y.resize(nv, 0.0);
            for (i, c) in couplings.iter().enumerate() {
                y[ov + c.coordinate] += c.multiplier * f[ov + i];
            }
            y
        };
        let column = |i: usize| -> Vec<(usize, f64)> {
            if i < ov {
                return vec![(i, 1.0)];
            }
            couplings
                .iter()
                .enumerate()
                .filter(|(_, c)| c.coordinate == i - ov)
                .map(|(j, c)| (ov + j, c.multiplier))
                .collect()
        };
        let zeros_p = vec![0.0; nv_p];
        let zeros = vec![0.0; nv];
        let m_p = eval(&p, &p.mass_matrix, &q_p, &v_p, &a_p, &zeros_p);
        let m_expected: Vec<f64> = (0..nv * nv)
            .map(|e| {
                let (rows, cols) = (column(e / nv), column(e % nv));
                rows.iter()
                    .flat_map(|&(i, wi)| cols.iter().map(move |&(j, wj)| (i, j, wi * wj)))
                    .map(|(i, j, w)| w * m_p[i * nv_p + j])
                    .sum()
            })
            .collect();
        let m = eval(&d, &d.mass_matrix, &q, &v, &a, &zeros);
        close(&format!("robot {k} M"), &m, &m_expected);
        for (name, roots, roots_p) in [
            ("c", &d.coriolis, &p.coriolis),
            ("g", &d.gravity, &p.gravity),
            ("τ", &d.inverse_dynamics, &p.inverse_dynamics),
        ] {
            let x = eval(&d, roots, &q, &v, &a, &zeros);
            let y = jt(&eval(&p, roots_p, &q_p, &v_p, &a_p, &zeros_p));
            close(&format!("robot {k} {name}"), &x, &y);
        }
        let tau = eval(&d, &d.inverse_dynamics, &q, &v, &a, &zeros);
        let back = eval(&d, &d.forward_dynamics, &q, &v, &zeros, &tau);
        close(&format!("robot {k} FD(ID)"), &back, &a);
        for i in 0..nv {
            for j in 0..nv {
                assert_eq!(m[i * nv + j], m[j * nv + i], "robot {k}: M not symmetric");
                let related = column(i).iter().any(|&(a, _)| {
                    column(j).iter().any(|&(b, _)| {
                        a < ov
                            || b < ov
                            || r.path_to(a - ov).contains(&(b - ov))
                            || r.path_to(b - ov).contains(&(a - ov))
                    })
                });
                if !related {
                    assert!(
                        d.graph.is_zero(d.mass_matrix[i * nv + j]),
                        "robot {k}: M[{i}][{j}] is built"
                    );
                }
            }
        }
    }
}

/// A robot without mimic joints expands exactly as before: the coupling is the identity and
/// adds no node.
#[test]
fn no_mimic_no_change() {
    let r = random_tree(
        3,
        TreeSpec {
            dof: 6,
            prismatic: 0.3,
            branching: 0.4,
            floating: true,
        },
    );
    let c = mimic::Coupling::new(&r);
    assert!(c.is_identity());
    let mut g = ExprGraph::new();
    let x: Vec<ExprId> = (0..r.nv()).map(|i| g.input(input(QD, i))).collect();
    let len = g.len();
    assert_eq!(c.rates(&mut g, &x), x);
    assert_eq!(c.forces(&mut g, &x), x);
    assert_eq!(g.len(), len);
}
