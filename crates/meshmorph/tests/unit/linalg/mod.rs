mod block_chain;
mod matrix;
pub(crate) mod polar;
mod quaternion;
mod similarity;
mod trig;
mod vector;
