#include "daemon/modbus/modbus_server.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <modbus/modbus.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <spdlog/spdlog.h>
#include <sys/select.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <mutex>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "daemon/modbus/register_map.hpp"

namespace tlsmon {

namespace {

using Clock = std::chrono::steady_clock;

// MBAP header (Modbus Messaging on TCP/IP Implementation Guide V1.0b, 3.1.3): transaction
// id (2), protocol id (2, = 0), length (2, bytes that follow: unit id + PDU), unit id (1).
constexpr std::size_t kMbapBytes = 7;
constexpr std::size_t kMaxAdu = 260;  // 7 + 253-byte PDU
constexpr int kTickMs = 100;          // select() timeout: heartbeat and idle checks

struct Client {
    int fd = -1;
    std::string peer;
    std::vector<std::uint8_t> buffer;  // bytes of an incomplete request
    Clock::time_point last_request;
};

std::uint16_t be16(const std::uint8_t* p) {
    return static_cast<std::uint16_t>((p[0] << 8) | p[1]);
}

void set_nonblocking(int fd) {
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) | O_NONBLOCK);
}

}  // namespace

struct ModbusServer::State {
    ModbusConfig config;
    AcknowledgeRequest acknowledge;
    modbus_t* ctx = nullptr;
    modbus_mapping_t* mapping = nullptr;
    std::vector<std::string> coil_rules;
    int listen_fd = -1;
    int wake[2] = {-1, -1};
    std::vector<Client> clients;
    std::atomic<bool> stop{false};
    std::mutex mutex;
    std::shared_ptr<const RegisterImage> pending;  // guarded by mutex
    Clock::time_point start = Clock::now();
    std::thread thread;

    void run();
    void take_image();
    void accept_client();
    // false: the connection is to be closed.
    bool read_from(Client& c);
    bool answer(Client& c, const std::uint8_t* frame, std::size_t size);
    bool coil_write_allowed(const std::uint8_t* pdu) const;
    void close_client(std::size_t i, const char* why);
    void set_heartbeat() {
        const auto s = std::chrono::duration_cast<std::chrono::seconds>(Clock::now() - start);
        if (mapping && mapping->nb_input_registers > kRegHeartbeat) {
            mapping->tab_input_registers[kRegHeartbeat] =
                static_cast<std::uint16_t>(s.count() & 0xFFFF);
        }
    }
};

ModbusServer::ModbusServer(const ModbusConfig& config, AcknowledgeRequest acknowledge)
    : state_(std::make_unique<State>()) {
    State& s = *state_;
    s.config = config;
    s.acknowledge = std::move(acknowledge);
    const std::string where = config.address + ":" + std::to_string(config.port);
    s.ctx = modbus_new_tcp(config.address.c_str(), config.port);
    if (!s.ctx) throw Error("modbus: cannot create a TCP context for " + where);
    s.listen_fd = modbus_tcp_listen(s.ctx, 16);
    if (s.listen_fd < 0) {
        const std::string why = modbus_strerror(errno);
        modbus_free(s.ctx);
        throw Error("modbus: cannot listen on " + where + ": " + why);
    }
    set_nonblocking(s.listen_fd);
    // The requests are checked before modbus_reply (request_exception); should libmodbus
    // still take an error path, its "sleep the response timeout, then flush" is 1 µs.
    modbus_set_response_timeout(s.ctx, 0, 1);
    if (::pipe2(s.wake, O_NONBLOCK | O_CLOEXEC) != 0) {
        ::close(s.listen_fd);
        modbus_free(s.ctx);
        throw Error("modbus: cannot create a pipe: " + std::string(std::strerror(errno)));
    }
    // An empty image until the first snapshot: the fixed registers answer at once.
    s.mapping = modbus_mapping_new(0, 0, 0, 0);
    s.thread = std::thread([&s] { s.run(); });
    spdlog::info("modbus: listening on {} (unit {}, word order {})", where, config.unit_id,
                 config.word_order == WordOrder::abcd ? "ABCD" : "CDAB");
}

ModbusServer::~ModbusServer() {
    State& s = *state_;
    s.stop = true;
    const char b = 0;
    [[maybe_unused]] auto n = ::write(s.wake[1], &b, 1);
    if (s.thread.joinable()) s.thread.join();
    for (auto& c : s.clients) ::close(c.fd);
    ::close(s.listen_fd);
    ::close(s.wake[0]);
    ::close(s.wake[1]);
    if (s.mapping) modbus_mapping_free(s.mapping);
    modbus_free(s.ctx);
}

void ModbusServer::publish(std::shared_ptr<const RegisterImage> image) {
    State& s = *state_;
    {
        std::lock_guard lock(s.mutex);
        s.pending = std::move(image);
    }
    const char b = 1;
    [[maybe_unused]] auto n = ::write(s.wake[1], &b, 1);
}

void ModbusServer::State::take_image() {
    std::shared_ptr<const RegisterImage> image;
    {
        std::lock_guard lock(mutex);
        image = std::move(pending);
    }
    if (!image) return;
    const int nr = static_cast<int>(image->input_registers.size());
    const int nd = static_cast<int>(image->discrete_inputs.size());
    const int nc = static_cast<int>(image->coil_rules.size());
    if (mapping->nb_input_registers != nr || mapping->nb_input_bits != nd ||
        mapping->nb_bits != nc) {
        modbus_mapping_free(mapping);
        mapping = modbus_mapping_new(nc, nd, 0, nr);
        if (!mapping) throw Error("modbus: out of memory for the register mapping");
    }
    std::copy(image->input_registers.begin(), image->input_registers.end(),
              mapping->tab_input_registers);
    std::copy(image->discrete_inputs.begin(), image->discrete_inputs.end(),
              mapping->tab_input_bits);
    std::fill(mapping->tab_bits, mapping->tab_bits + nc, 0);
    coil_rules = image->coil_rules;
}

void ModbusServer::State::close_client(std::size_t i, const char* why) {
    spdlog::debug("modbus: {} disconnected: {}", clients[i].peer, why);
    ::close(clients[i].fd);
    clients.erase(clients.begin() + static_cast<std::ptrdiff_t>(i));
}

void ModbusServer::State::accept_client() {
    while (true) {
        sockaddr_in addr{};
        socklen_t len = sizeof addr;
        const int fd = ::accept4(listen_fd, reinterpret_cast<sockaddr*>(&addr), &len,
                                 SOCK_NONBLOCK | SOCK_CLOEXEC);
        if (fd < 0) return;  // EAGAIN: none left
        char text[INET_ADDRSTRLEN] = {};
        ::inet_ntop(AF_INET, &addr.sin_addr, text, sizeof text);
        const std::string address = text;
        const std::string peer = address + ":" + std::to_string(ntohs(addr.sin_port));
        const auto& allow = config.allowlist;
        if (!allow.empty() && std::find(allow.begin(), allow.end(), address) == allow.end()) {
            spdlog::warn("modbus: connection from {} refused: not in modbus.allowlist", peer);
            ::close(fd);
            continue;
        }
        if (clients.size() >= static_cast<std::size_t>(config.max_clients) || fd >= FD_SETSIZE) {
            spdlog::warn("modbus: connection from {} refused: {} clients connected (max_clients)",
                         peer, clients.size());
            ::close(fd);
            continue;
        }
        const int one = 1;
        ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
        clients.push_back({fd, peer, {}, Clock::now()});
    }
}

// Coil writes go only to acknowledge coils of this map (not to its unused addresses).
bool ModbusServer::State::coil_write_allowed(const std::uint8_t* pdu) const {
    const int address = be16(pdu + 1);
    const int count = pdu[0] == MODBUS_FC_WRITE_SINGLE_COIL ? 1 : be16(pdu + 3);
    if (count < 1) return false;
    for (int a = address; a < address + count; ++a) {
        if (a >= static_cast<int>(coil_rules.size()) ||
            coil_rules[static_cast<std::size_t>(a)].empty())
            return false;
    }
    return true;
}

// An exception response built here, not by modbus_reply_exception, which adds 0x80 to a
// function code in a byte: a request with a code of 0x80 or above (0x84) got a reply
// with the code of another function (0x04) and a malformed body.
static bool send_exception(int fd, const std::uint8_t* frame, std::uint8_t code) {
    const std::uint8_t reply[9] = {
        frame[0], frame[1], 0,        0,
        0,        3,        frame[6], static_cast<std::uint8_t>(frame[kMbapBytes] | 0x80),
        code};
    return ::send(fd, reply, sizeof reply, MSG_NOSIGNAL) == static_cast<ssize_t>(sizeof reply);
}

// Why a request may not reach modbus_reply (the exception code), 0 when it may. libmodbus
// answers a quantity or an address out of range itself, but first sleeps its response
// timeout and flushes the socket, in this one server thread: every request is checked here
// so that it never does (Modbus Application Protocol V1.1b3, 6.1-6.11: quantities 1..2000
// bits, 1..125 registers, 1..1968 coils written).
static std::uint8_t request_exception(const std::uint8_t* pdu, std::size_t pdu_size,
                                      const modbus_mapping_t& mapping) {
    const int function = pdu[0];
    const auto within = [](int address, int count, int size) {
        return address + count <= size ? 0 : MODBUS_EXCEPTION_ILLEGAL_DATA_ADDRESS;
    };
    switch (function) {
        case MODBUS_FC_READ_COILS:
        case MODBUS_FC_READ_DISCRETE_INPUTS:
        case MODBUS_FC_READ_INPUT_REGISTERS: {
            if (pdu_size != 5) return MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE;
            const int address = be16(pdu + 1);
            const int count = be16(pdu + 3);
            const bool registers = function == MODBUS_FC_READ_INPUT_REGISTERS;
            if (count < 1 || count > (registers ? MODBUS_MAX_READ_REGISTERS : MODBUS_MAX_READ_BITS))
                return MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE;
            const int size = function == MODBUS_FC_READ_COILS ? mapping.nb_bits
                             : registers                      ? mapping.nb_input_registers
                                                              : mapping.nb_input_bits;
            return static_cast<std::uint8_t>(within(address, count, size));
        }
        case MODBUS_FC_WRITE_SINGLE_COIL: {
            if (pdu_size != 5) return MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE;
            const int value = be16(pdu + 3);
            if (value != 0xFF00 && value != 0x0000) return MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE;
            return static_cast<std::uint8_t>(within(be16(pdu + 1), 1, mapping.nb_bits));
        }
        case MODBUS_FC_WRITE_MULTIPLE_COILS: {
            if (pdu_size < 6 || pdu_size != 6u + pdu[5]) return MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE;
            const int count = be16(pdu + 3);
            if (count < 1 || count > MODBUS_MAX_WRITE_BITS || pdu[5] != (count + 7) / 8)
                return MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE;
            return static_cast<std::uint8_t>(within(be16(pdu + 1), count, mapping.nb_bits));
        }
        case MODBUS_FC_READ_HOLDING_REGISTERS:
        case MODBUS_FC_WRITE_SINGLE_REGISTER:
        case MODBUS_FC_WRITE_MULTIPLE_REGISTERS:
        case MODBUS_FC_WRITE_AND_READ_REGISTERS:
        case MODBUS_FC_MASK_WRITE_REGISTER:
            return MODBUS_EXCEPTION_ILLEGAL_DATA_ADDRESS;  // no holding registers
        default:
            return MODBUS_EXCEPTION_ILLEGAL_FUNCTION;
    }
}

bool ModbusServer::State::answer(Client& c, const std::uint8_t* frame, std::size_t size) {
    if (frame[6] != config.unit_id) return true;  // another unit's request: not ours to answer
    const std::uint8_t* pdu = frame + kMbapBytes;
    const int function = pdu[0];
    if (const std::uint8_t code = request_exception(pdu, size - kMbapBytes, *mapping)) {
        return send_exception(c.fd, frame, code);
    }
    const bool coil_write =
        function == MODBUS_FC_WRITE_SINGLE_COIL || function == MODBUS_FC_WRITE_MULTIPLE_COILS;
    if (coil_write && (!config.writable_coils || !coil_write_allowed(pdu))) {
        return send_exception(c.fd, frame, MODBUS_EXCEPTION_ILLEGAL_DATA_ADDRESS);
    }
    set_heartbeat();
    modbus_set_socket(ctx, c.fd);
    if (modbus_reply(ctx, frame, static_cast<int>(size), mapping) < 0) return false;
    if (coil_write) {
        // Self-resetting: each coil written to 1 is one acknowledge request, then reads 0.
        for (int i = 0; i < mapping->nb_bits; ++i) {
            if (mapping->tab_bits[i]) {
                mapping->tab_bits[i] = 0;
                const auto& rule = coil_rules[static_cast<std::size_t>(i)];
                if (!rule.empty()) {
                    spdlog::info("modbus: {} acknowledges {}", c.peer,
                                 rule == "*" ? std::string("every alarm") : "rule " + rule);
                    acknowledge(rule, c.peer);
                }
            }
        }
    }
    return true;
}

bool ModbusServer::State::read_from(Client& c) {
    std::uint8_t chunk[1024];
    while (true) {
        const ssize_t n = ::recv(c.fd, chunk, sizeof chunk, 0);
        if (n == 0) return false;
        if (n < 0) return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR;
        c.buffer.insert(c.buffer.end(), chunk, chunk + n);
        while (c.buffer.size() >= 6) {
            const std::uint16_t protocol = be16(c.buffer.data() + 2);
            const std::uint16_t length = be16(c.buffer.data() + 4);
            // Not Modbus (or a frame longer than the protocol allows): the stream cannot be
            // resynchronised, so the connection is closed.
            if (protocol != 0 || length < 2 || length + 6u > kMaxAdu) return false;
            const std::size_t size = 6u + length;
            if (c.buffer.size() < size) break;
            c.last_request = Clock::now();
            if (!answer(c, c.buffer.data(), size)) return false;
            c.buffer.erase(c.buffer.begin(), c.buffer.begin() + static_cast<std::ptrdiff_t>(size));
        }
        if (static_cast<std::size_t>(n) < sizeof chunk) return true;
    }
}

void ModbusServer::State::run() {
    try {
        while (!stop) {
            fd_set read_set;
            FD_ZERO(&read_set);
            FD_SET(wake[0], &read_set);
            FD_SET(listen_fd, &read_set);
            int top = std::max(wake[0], listen_fd);
            for (const auto& c : clients) {
                FD_SET(c.fd, &read_set);
                top = std::max(top, c.fd);
            }
            timeval timeout{0, kTickMs * 1000};
            const int ready = ::select(top + 1, &read_set, nullptr, nullptr, &timeout);
            if (ready < 0 && errno != EINTR)
                throw Error("modbus: select: " + std::string(std::strerror(errno)));
            if (stop) break;
            if (ready > 0 && FD_ISSET(wake[0], &read_set)) {
                char drain[64];
                while (::read(wake[0], drain, sizeof drain) > 0) {
                }
            }
            take_image();
            set_heartbeat();
            if (ready > 0) {
                for (std::size_t i = clients.size(); i-- > 0;) {
                    if (FD_ISSET(clients[i].fd, &read_set) && !read_from(clients[i])) {
                        close_client(i, "closed, or not a Modbus TCP stream");
                    }
                }
                if (FD_ISSET(listen_fd, &read_set)) accept_client();
            }
            const auto idle_limit = std::chrono::duration_cast<Clock::duration>(
                std::chrono::duration<double>(config.idle_timeout));
            const auto now = Clock::now();
            for (std::size_t i = clients.size(); i-- > 0;) {
                if (now - clients[i].last_request > idle_limit) close_client(i, "idle");
            }
        }
    } catch (const std::exception& e) {
        spdlog::critical("modbus server stopped: {}", e.what());
    }
}

}  // namespace tlsmon
