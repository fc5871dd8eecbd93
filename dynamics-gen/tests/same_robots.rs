//! Every front end accepts and refuses exactly the same robots: a robot whose mass matrix is
//! singular for every q (a massless tip link, a joint that moves nothing) is refused by
//! `generate`, `stats`, `eval` and `joints`, the Builder and the macros, with one message
//! naming the file, the joint, the field and the fix; never `1.0 / 0.0` in generated code.

use quote::quote;
use std::path::PathBuf;
use std::process::Command;

/// A two-joint arm whose second link is `tip_inertial` (empty: massless).
fn urdf(tip_inertial: &str) -> String {
    format!(
        r#"<robot name="arm">
  <link name="base"/>
  <link name="upper"><inertial><origin xyz="0 0 0.2"/><mass value="1"/>
    <inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="hand">{tip_inertial}</link>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="10" velocity="2"/></joint>
  <joint name="wrist" type="revolute"><parent link="upper"/><child link="hand"/>
    <origin xyz="0 0 0.4"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="10" velocity="2"/></joint>
</robot>
"#
    )
}

/// Point mass on the wrist's own axis: the wrist moves no mass or inertia either.
const ON_AXIS: &str = r#"<inertial><origin xyz="0 0.3 0"/><mass value="1"/>
    <inertia ixx="0" iyy="0" izz="0" ixy="0" ixz="0" iyz="0"/></inertial>"#;

fn write(tag: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("dynamics-gen-same-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("arm.urdf");
    std::fs::write(&path, text).unwrap();
    path
}

fn assert_names_the_wrist(msg: &str, file: &str) {
    for part in [
        file,
        "joint `wrist`",
        "field `inertia`",
        "singular for every q",
        "`hand`",
        "fix:",
    ] {
        assert!(msg.contains(part), "`{part}` missing from: {msg}");
    }
}

#[test]
fn a_singular_mass_matrix_is_refused_by_every_front_end() {
    for (tag, inertial) in [("massless", ""), ("on_axis", ON_AXIS)] {
        let path = write(tag, &urdf(inertial));
        let file = path.to_str().unwrap();
        for sub in ["generate", "stats", "eval", "joints"] {
            let out = Command::new(env!("CARGO_BIN_EXE_dynamics-gen"))
                .args([sub, file])
                .output()
                .unwrap();
            let err = String::from_utf8(out.stderr).unwrap();
            assert_eq!(out.status.code(), Some(1), "{tag} {sub}: {err}");
            assert!(out.stdout.is_empty(), "{tag} {sub}");
            assert_names_the_wrist(&err, file);
        }
        let err = dynamics_gen::Builder::new(file)
            .generate()
            .unwrap_err()
            .to_string();
        assert_names_the_wrist(&err, file);
        let tokens = dynamics_gen::macro_support::derive_dynamics(quote! {
            #[dynamics(file = #file)]
            pub struct Arm;
        })
        .to_string();
        assert!(tokens.contains("compile_error"), "{tokens}");
        assert!(tokens.contains("singular for every q"), "{tokens}");
        std::fs::remove_dir_all(path.parent().unwrap()).unwrap();
    }
}

#[test]
fn the_same_arm_with_a_tip_mass_is_accepted_everywhere() {
    let inertial = r#"<inertial><origin xyz="0.1 0 0"/><mass value="0.5"/>
    <inertia ixx="0.001" iyy="0.001" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial>"#;
    let path = write("good", &urdf(inertial));
    let file = path.to_str().unwrap();
    for sub in ["generate", "stats", "joints"] {
        let out = Command::new(env!("CARGO_BIN_EXE_dynamics-gen"))
            .args([sub, file])
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{sub}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let code = dynamics_gen::Builder::new(file).generate().unwrap();
    assert!(!code.contains("/ 0.0"), "{code}");
    std::fs::remove_dir_all(path.parent().unwrap()).unwrap();
}
