mod consistency;
mod patches;
mod planar;
mod spatial;
