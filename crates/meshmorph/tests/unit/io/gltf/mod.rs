mod base64;
mod glb;
