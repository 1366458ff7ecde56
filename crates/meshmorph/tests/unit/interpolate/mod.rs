mod area_blend;
mod attached;
mod rotation;
mod sequence;
