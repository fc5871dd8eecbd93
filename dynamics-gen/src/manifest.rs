//! Reading the user's `Cargo.toml` for a dependency the generated code needs, so that a
//! missing one gets a hint instead of rustc's bare "unresolved crate".

use std::path::Path;

/// Hints for every dependency the code generated with `options` needs and the crate at
/// `manifest_dir` does not declare: `libm` for `no_std`, `dynamics-runtime` for the trait
/// impl at its default path.
pub fn missing_dependencies(manifest_dir: &Path, options: &crate::Options) -> Vec<String> {
    let mut hints = Vec::new();
    if options.no_std {
        hints.extend(missing_dependency(manifest_dir, "libm"));
    }
    if options.runtime_path.as_deref() == Some("::dynamics_runtime") {
        hints.extend(missing_dependency(manifest_dir, "dynamics-runtime"));
    }
    hints
}

/// A hint when the crate at `manifest_dir` declares no dependency named `krate` (in
/// `[dependencies]` or any `[target.*.dependencies]`, plain or renamed with `package =`);
/// `None` when it does, or when `Cargo.toml` cannot be read or parsed (nothing is guessed).
pub fn missing_dependency(manifest_dir: &Path, krate: &str) -> Option<String> {
    let text = std::fs::read_to_string(manifest_dir.join("Cargo.toml")).ok()?;
    let manifest: toml::Table = text.parse().ok()?;
    let declares = |deps: Option<&toml::Value>| {
        deps.and_then(toml::Value::as_table).is_some_and(|t| {
            t.iter().any(|(name, spec)| {
                name == krate || spec.get("package").and_then(|p| p.as_str()) == Some(krate)
            })
        })
    };
    let mut found = declares(manifest.get("dependencies"));
    if let Some(targets) = manifest.get("target").and_then(toml::Value::as_table) {
        found |= targets.values().any(|t| declares(t.get("dependencies")));
    }
    (!found).then(|| match krate {
        "libm" => "no_std code calls `::libm` for sin/cos, but Cargo.toml has no `libm` dependency: add `libm = \"0.2\"` under [dependencies]".to_string(),
        _ => format!(
            "the generated struct implements `{}::Dynamics`, but Cargo.toml has no `{krate}` dependency: add `{krate} = \"0.1\"` under [dependencies], or call .no_runtime_trait()",
            krate.replace('-', "_")
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::missing_dependency;

    fn manifest(text: &str) -> Option<String> {
        let dir = std::env::temp_dir().join(format!(
            "dynamics-gen-manifest-{}-{}",
            std::process::id(),
            text.len()
        ));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("Cargo.toml"), text).unwrap();
        let out = missing_dependency(&dir, "libm");
        std::fs::remove_dir_all(&dir).unwrap();
        out
    }

    #[test]
    fn finds_plain_renamed_and_target_dependencies() {
        assert!(manifest("[dependencies]\nlibm = \"0.2\"\n").is_none());
        assert!(
            manifest("[dependencies]\nm = { package = \"libm\", version = \"0.2\" }\n").is_none()
        );
        assert!(
            manifest("[target.'cfg(target_os = \"none\")'.dependencies]\nlibm = \"0.2\"\n")
                .is_none()
        );
        assert!(manifest("[dependencies]\nlibm.workspace = true\n").is_none());
        let hint = manifest("[dependencies]\nnalgebra = \"0.35\"\n").unwrap();
        assert!(hint.contains("libm = \"0.2\""), "{hint}");
        assert!(manifest("not toml [").is_none());
    }
}
