//! Area weights: each term of an energy counts in proportion to the area it
//! covers, so that the result does not depend on how finely a surface is
//! tessellated.

/// Divides every value by their mean, so that they average 1 (a weight of
/// 1 is then "an average triangle", whatever the mesh's scale).
pub fn normalise_by_mean(values: &mut [f64]) {
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    values.iter_mut().for_each(|x| *x /= mean);
}

/// `values` divided by their mean.
pub fn normalised_by_mean(values: &[f64]) -> Vec<f64> {
    let mut v = values.to_vec();
    normalise_by_mean(&mut v);
    v
}

/// The weight of each of `num_vertices` vertices: a third of the weight of
/// every triangle around it (its share of their area when the triangle
/// weights are areas). Vertices no triangle uses weigh 0.
pub fn vertex_weights(
    num_vertices: usize,
    triangles: &[[u32; 3]],
    triangle_weights: &[f64],
) -> Vec<f64> {
    let mut w = vec![0.0; num_vertices];
    for (tri, a) in triangles.iter().zip(triangle_weights) {
        for &v in tri {
            w[v as usize] += a / 3.0;
        }
    }
    w
}
