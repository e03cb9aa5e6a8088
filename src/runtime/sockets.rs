//! The two UDP sockets of one vehicle's links (GCS and API), bound with a large receive buffer.

use std::net::SocketAddr;

use tokio::net::UdpSocket;

use crate::mav::streams::LinkKind;

/// The largest datagram read whole [bytes]: 29 MAVLink 2 frames of the largest size (280 bytes,
/// signed). The kernel cuts longer datagrams to this (PX4 reads 1,600 bytes), so a flood of
/// 64 KiB garbage costs no more to skip than a flood of small ones.
pub(super) const MAX_DATAGRAM_BYTES: usize = 8_192;

/// The GCS and API sockets of one vehicle.
pub struct LinkSockets(pub(super) [(LinkKind, UdpSocket); 2]);

impl LinkSockets {
    /// The GCS socket bound at `gcs` and the API socket at `api`, registered with `rt`; or the
    /// address that could not be bound, and why.
    pub fn bind(
        rt: &tokio::runtime::Runtime,
        gcs: SocketAddr,
        api: SocketAddr,
    ) -> Result<Self, (SocketAddr, std::io::Error)> {
        let _guard = rt.enter();
        let bind = |addr| bind_udp(addr).map_err(|e| (addr, e));
        Ok(Self([(LinkKind::Gcs, bind(gcs)?), (LinkKind::Api, bind(api)?)]))
    }

    /// The bound GCS and API addresses.
    pub fn local_addrs(&self) -> (String, String) {
        let local = |s: &UdpSocket| s.local_addr().map(|a| a.to_string()).unwrap_or_default();
        (local(&self.0[0].1), local(&self.0[1].1))
    }

    /// The socket of `link`.
    pub(super) fn socket(&self, link: LinkKind) -> &UdpSocket {
        let [(_, gcs), (kind, api)] = &self.0;
        if *kind == link {
            api
        } else {
            gcs
        }
    }
}

/// Kernel receive buffer of each link socket [bytes]: large enough that a burst of garbage
/// datagrams does not make the kernel drop the legitimate command behind it.
const RECV_BUFFER_BYTES: usize = 4 << 20;

/// A non-blocking UDP socket bound to `addr` with a large receive buffer, for tokio.
fn bind_udp(addr: SocketAddr) -> std::io::Result<UdpSocket> {
    let socket = socket2::Socket::new(socket2::Domain::for_address(addr), socket2::Type::DGRAM, None)?;
    // Best effort: the kernel caps it at net.core.rmem_max.
    let _ = socket.set_recv_buffer_size(RECV_BUFFER_BYTES);
    socket.set_nonblocking(true)?;
    socket.bind(&addr.into())?;
    UdpSocket::from_std(socket.into())
}
