//! Facial expressions put on any head from a few landmarks: a template rig
//! (ICT-FaceKit's head with the ARKit shapes, shipped in
//! `templates/arkit.glb`, or a studio's own), the landmark names, ARKit's
//! shape names, and the carrying of each shape onto the user's head.

pub mod arkit_names;
pub mod carry;
pub mod identity;
pub mod landmark_file;
pub mod landmarks;
pub mod openings;
pub mod places;
pub mod template;
pub mod template_file;
