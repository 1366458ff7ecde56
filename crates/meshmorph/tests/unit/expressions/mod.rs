mod arkit_names;
mod carry;
mod identity;
mod landmarks;
mod openings;
mod places;
mod template;
