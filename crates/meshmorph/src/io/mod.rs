//! Reading and writing meshes: OBJ, OFF and PLY.
