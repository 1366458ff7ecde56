//! Apple's 52 ARKit blendshape names and how each is made from a
//! template's shapes: ICT-FaceKit names the sides `_L` and `_R` (the head's
//! own left and right, as ARKit's `Left` and `Right`), splits `browInnerUp`
//! and `cheekPuff` into halves (both together make ARKit's one shape) and
//! has no `tongueOut`.

/// ARKit's 52 blendshape names, in Apple's documentation's order.
pub const ARKIT_NAMES: [&str; 52] = [
    "eyeBlinkLeft",
    "eyeLookDownLeft",
    "eyeLookInLeft",
    "eyeLookOutLeft",
    "eyeLookUpLeft",
    "eyeSquintLeft",
    "eyeWideLeft",
    "eyeBlinkRight",
    "eyeLookDownRight",
    "eyeLookInRight",
    "eyeLookOutRight",
    "eyeLookUpRight",
    "eyeSquintRight",
    "eyeWideRight",
    "jawForward",
    "jawLeft",
    "jawRight",
    "jawOpen",
    "mouthClose",
    "mouthFunnel",
    "mouthPucker",
    "mouthLeft",
    "mouthRight",
    "mouthSmileLeft",
    "mouthSmileRight",
    "mouthFrownLeft",
    "mouthFrownRight",
    "mouthDimpleLeft",
    "mouthDimpleRight",
    "mouthStretchLeft",
    "mouthStretchRight",
    "mouthRollLower",
    "mouthRollUpper",
    "mouthShrugLower",
    "mouthShrugUpper",
    "mouthPressLeft",
    "mouthPressRight",
    "mouthLowerDownLeft",
    "mouthLowerDownRight",
    "mouthUpperUpLeft",
    "mouthUpperUpRight",
    "browDownLeft",
    "browDownRight",
    "browInnerUp",
    "browOuterUpLeft",
    "browOuterUpRight",
    "cheekPuff",
    "cheekSquintLeft",
    "cheekSquintRight",
    "noseSneerLeft",
    "noseSneerRight",
    "tongueOut",
];

/// One output shape: its name and the template shapes whose deltas it sums.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ShapeRecipe {
    /// The output's name.
    pub name: String,
    /// Indices of the template's shapes, summed.
    pub sources: Vec<usize>,
}

/// The output shapes from a template's shape names: ARKit's 52 in order
/// (each found under its own name, or as `_L` / `_R`, or as both halves),
/// then with `all_shapes` the template's other shapes under their own
/// names. Returns the recipes and the ARKit names the template lacks.
pub fn arkit_recipes(
    template_names: &[String],
    all_shapes: bool,
) -> (Vec<ShapeRecipe>, Vec<String>) {
    let find = |n: &str| template_names.iter().position(|t| t == n);
    let mut used = vec![false; template_names.len()];
    let mut recipes = Vec::new();
    let mut missing = Vec::new();
    for &name in &ARKIT_NAMES {
        let sources = if let Some(k) = find(name) {
            vec![k]
        } else if let Some(base) = name.strip_suffix("Left") {
            find(&format!("{base}_L")).into_iter().collect()
        } else if let Some(base) = name.strip_suffix("Right") {
            find(&format!("{base}_R")).into_iter().collect()
        } else {
            match (find(&format!("{name}_L")), find(&format!("{name}_R"))) {
                (Some(l), Some(r)) => vec![l, r],
                _ => Vec::new(),
            }
        };
        if sources.is_empty() {
            missing.push(name.to_string());
        } else {
            sources.iter().for_each(|&k| used[k] = true);
            recipes.push(ShapeRecipe {
                name: name.to_string(),
                sources,
            });
        }
    }
    if all_shapes {
        for (k, name) in template_names.iter().enumerate() {
            if !used[k] {
                recipes.push(ShapeRecipe {
                    name: name.clone(),
                    sources: vec![k],
                });
            }
        }
    }
    (recipes, missing)
}
