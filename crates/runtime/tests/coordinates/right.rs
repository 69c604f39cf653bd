//! A declaration without mistakes compiles: a free cart.

include!("carts.rs");

cart!(free_cart, x_ddot: Variable::output("m/s2"), 1 coordinates: [Coordinate::free("x")]);

fn main() {
    free_cart::compile();
}
