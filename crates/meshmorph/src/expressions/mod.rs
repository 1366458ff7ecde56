//! Facial expressions put on any head from a few landmarks: a template rig
//! (ICT-FaceKit's head with the ARKit shapes, shipped in
//! `templates/arkit.glb`, or a studio's own), the landmark names, ARKit's
//! shape names, and the carrying of each shape onto the user's head.

pub(crate) mod arkit_names;
pub(crate) mod carry;
pub(crate) mod identity;
pub(crate) mod landmark_file;
pub(crate) mod landmarks;
pub(crate) mod openings;
pub(crate) mod places;
pub(crate) mod template;
pub(crate) mod template_file;
