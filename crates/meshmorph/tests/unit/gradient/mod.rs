mod solve;
mod spatial;
