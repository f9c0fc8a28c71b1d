#pragma once
// A minimal Modbus TCP client on a plain socket (no libmodbus: the tests and the bench talk
// to the server as an independent party), also able to send what a good client never would.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdint>
#include <optional>
#include <vector>

namespace tlsmon::test {

// A TCP port nobody listens on now: the kernel's choice for port 0.
inline int free_tcp_port() {
    const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
    socklen_t len = sizeof a;
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
    ::close(fd);
    return ntohs(a.sin_port);
}

class ModbusTcpClient {
  public:
    ModbusTcpClient() = default;
    ~ModbusTcpClient() { close(); }
    ModbusTcpClient(const ModbusTcpClient&) = delete;
    ModbusTcpClient& operator=(const ModbusTcpClient&) = delete;

    bool connect(int port) {
        close();
        fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_port = htons(static_cast<std::uint16_t>(port));
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        if (::connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
            close();
            return false;
        }
        const int one = 1;
        ::setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
        return true;
    }
    void close() {
        if (fd_ >= 0) ::close(fd_);
        fd_ = -1;
    }
    bool connected() const { return fd_ >= 0; }

    bool send_bytes(const std::vector<std::uint8_t>& bytes) {
        return fd_ >= 0 && ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL) ==
                               static_cast<ssize_t>(bytes.size());
    }

    std::uint8_t unit = 1;  // the unit id of the requests

    // A request ADU: MBAP header + PDU.
    std::vector<std::uint8_t> frame(const std::vector<std::uint8_t>& pdu) {
        ++tid_;
        const auto len = static_cast<std::uint16_t>(pdu.size() + 1);
        std::vector<std::uint8_t> f = {
            static_cast<std::uint8_t>(tid_ >> 8), static_cast<std::uint8_t>(tid_ & 0xFF), 0,   0,
            static_cast<std::uint8_t>(len >> 8),  static_cast<std::uint8_t>(len & 0xFF),  unit};
        f.insert(f.end(), pdu.begin(), pdu.end());
        return f;
    }

    // The response PDU to `pdu` (function, data...), or nullopt on timeout / closed / a
    // response that does not match the transaction.
    std::optional<std::vector<std::uint8_t>> request(const std::vector<std::uint8_t>& pdu,
                                                     int timeout_ms = 1000) {
        if (!send_bytes(frame(pdu))) return std::nullopt;
        std::vector<std::uint8_t> in;
        while (true) {
            if (in.size() >= 6) {
                const std::size_t need = 6u + ((in[4] << 8) | in[5]);
                if (in.size() >= need) {
                    if (((in[0] << 8) | in[1]) != tid_) return std::nullopt;
                    return std::vector<std::uint8_t>(in.begin() + 7, in.begin() + need);
                }
            }
            pollfd p{fd_, POLLIN, 0};
            if (::poll(&p, 1, timeout_ms) <= 0) return std::nullopt;
            std::uint8_t buf[300];
            const ssize_t n = ::recv(fd_, buf, sizeof buf, 0);
            if (n <= 0) {
                close();
                return std::nullopt;
            }
            in.insert(in.end(), buf, buf + n);
        }
    }

    std::optional<std::vector<std::uint16_t>> read_input_registers(int address, int count,
                                                                   int timeout_ms = 1000) {
        const auto r = request(
            {4, static_cast<std::uint8_t>(address >> 8), static_cast<std::uint8_t>(address & 0xFF),
             0, static_cast<std::uint8_t>(count)},
            timeout_ms);
        if (!r || r->size() != 2u + 2u * count || (*r)[0] != 4) return std::nullopt;
        std::vector<std::uint16_t> out;
        for (int i = 0; i < count; ++i)
            out.push_back(static_cast<std::uint16_t>(((*r)[2 + 2 * i] << 8) | (*r)[3 + 2 * i]));
        return out;
    }

    // True once the server has closed the connection (within `timeout_ms`).
    bool closed_by_peer(int timeout_ms) {
        pollfd p{fd_, POLLIN, 0};
        if (::poll(&p, 1, timeout_ms) <= 0) return false;
        std::uint8_t b;
        return ::recv(fd_, &b, 1, 0) <= 0;
    }

  private:
    int fd_ = -1;
    std::uint16_t tid_ = 0;
};

}  // namespace tlsmon::test
