//! The GLSL constants header and its Rust mirror agree, name for name.

use std::collections::BTreeMap;

use bezier_subdiv::constants::ALL;

fn parse_consts(text: &str, prefix: &str, sep: &str) -> BTreeMap<String, u32> {
    let mut out = BTreeMap::new();
    for line in text.lines() {
        let Some(rest) = line.trim().strip_prefix(prefix) else {
            continue;
        };
        let Some((name, value)) = rest.split_once(sep) else {
            continue;
        };
        let value = value.split("//").next().unwrap().trim();
        let value = value.trim_end_matches(';').trim();
        let value = value.replace('_', "");
        let v = match value.strip_prefix("0x") {
            Some(h) => u32::from_str_radix(h, 16),
            None => value.parse(),
        }
        .unwrap_or_else(|_| panic!("bad value in: {line}"));
        assert!(
            out.insert(name.trim().to_string(), v).is_none(),
            "duplicate {name}"
        );
    }
    out
}

#[test]
fn glsl_and_rust_constants_agree() {
    let root = env!("CARGO_MANIFEST_DIR");
    let glsl = std::fs::read_to_string(format!("{root}/glsl/common/constants.glsl")).unwrap();
    let rust_src = std::fs::read_to_string(format!("{root}/src/constants.rs")).unwrap();
    let from_glsl = parse_consts(&glsl, "const uint ", "=");
    let declared = parse_consts(&rust_src, "pub const ", ": u32 =");
    let listed: BTreeMap<String, u32> = ALL.iter().map(|(n, v)| (n.to_string(), *v)).collect();
    assert!(
        from_glsl.len() > 40,
        "parsed {} GLSL constants",
        from_glsl.len()
    );
    assert_eq!(
        from_glsl, declared,
        "glsl/common/constants.glsl vs src/constants.rs"
    );
    assert_eq!(declared, listed, "constants::ALL must list every constant");
}
