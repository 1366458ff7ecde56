mod bvh;
mod closest;
mod nearest_vertices;
mod seams;
mod shapes;
mod surface_point;
mod topology;
mod triangle_mesh;
