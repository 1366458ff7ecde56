mod carried_parts;
mod fit_report;
mod markers;
mod matching;
mod mirror_plane;
mod partner_parts;
