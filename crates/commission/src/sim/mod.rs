//! The simulator: the crate `canctl-sim` (devices, the simulated bus, the serial and
//! socketcand device sides), and [`serve`], the simulated network served as `canctl sim`
//! serves it, which opens buses by address and so sits above [`crate::connect`].

pub use canctl_sim::*;
pub mod serve;

/// The default network on virtual time behind the client every command uses (seed 1): what
/// the library's unit tests of a procedure run on.
#[cfg(test)]
pub(crate) fn test_bus() -> crate::bus::Master<SimLink> {
    let config = SimConfig::default().seed(1).virtual_time(true);
    crate::bus::Master::new(SimLink::with_config(config).on_virtual_time(0), "sim".into())
}
