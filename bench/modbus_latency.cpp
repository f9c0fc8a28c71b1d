// Request latency of the Modbus server under the load: 20 clients each reading
// 10 input registers at 10 Hz, beside 5 idle connections, 3 clients sending random bytes,
// 3 sending truncated frames and 2 writing to read-only addresses. The server is the
// daemon's (ModbusServer, one thread, a rendered register image of 20 zones and 40 rules);
// the clients are plain sockets. Prints p50/p99/max of the well-behaved requests.
//   bench_modbus_latency [seconds=10]
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <random>
#include <thread>
#include <vector>

#include "daemon/modbus/modbus_server.hpp"
#include "daemon/modbus/register_image.hpp"
#include "daemon/modbus/register_map.hpp"
#include "tests/support/modbus_client.hpp"

using namespace tlsmon;
using Clock = std::chrono::steady_clock;

int main(int argc, char** argv) {
    const double seconds = argc > 1 ? std::atof(argv[1]) : 10.0;
    ModbusConfig config;
    config.port = test::free_tcp_port();
    config.max_clients = 64;
    config.idle_timeout = 3600;
    MapInputs inputs;
    inputs.quantities = config.quantities;
    for (int z = 0; z < 20; ++z) inputs.zones.push_back({z, "zone " + std::to_string(z)});
    for (int r = 0; r < 40; ++r) inputs.rules.push_back({r, "rule " + std::to_string(r)});
    const RegisterMap map = build_register_map(inputs);
    ModbusSnapshot snapshot;
    snapshot.database_ok = true;
    ModbusServer server(config, [](const std::string&, const std::string&) {});
    server.publish(std::make_shared<const RegisterImage>(
        render_registers(map, inputs, snapshot, config.word_order)));
    std::this_thread::sleep_for(std::chrono::milliseconds(200));

    std::atomic<bool> stop{false};
    std::mutex mutex;
    std::vector<double> latencies_ms;
    std::atomic<int> lost{0};
    std::vector<std::thread> threads;
    for (int i = 0; i < 20; ++i) {
        threads.emplace_back([&, i] {
            test::ModbusTcpClient c;
            std::vector<double> mine;
            auto next = Clock::now() + std::chrono::milliseconds(5 * i);
            while (!stop) {
                std::this_thread::sleep_until(next);
                next += std::chrono::milliseconds(100);
                if (!c.connected() && !c.connect(config.port)) continue;
                const auto t0 = Clock::now();
                const auto r = c.read_input_registers(100 + 80 * (i % 20), 10, 2000);
                const auto t1 = Clock::now();
                if (r) {
                    mine.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
                } else {
                    ++lost;
                }
            }
            std::lock_guard lock(mutex);
            latencies_ms.insert(latencies_ms.end(), mine.begin(), mine.end());
        });
    }
    std::vector<std::unique_ptr<test::ModbusTcpClient>> idle;
    for (int i = 0; i < 5; ++i) {
        idle.push_back(std::make_unique<test::ModbusTcpClient>());
        idle.back()->connect(config.port);
    }
    for (int i = 0; i < 3; ++i) {
        threads.emplace_back([&, i] {
            std::mt19937 rng(static_cast<unsigned>(i + 7));
            test::ModbusTcpClient c;
            while (!stop) {
                if (!c.connected()) c.connect(config.port);
                std::vector<std::uint8_t> junk(1 + rng() % 300);
                for (auto& b : junk) b = static_cast<std::uint8_t>(rng());
                if (!c.send_bytes(junk)) c.close();
                std::this_thread::sleep_for(std::chrono::milliseconds(50));
            }
        });
        threads.emplace_back([&] {
            test::ModbusTcpClient c;
            while (!stop) {
                c.connect(config.port);
                auto f = c.frame({4, 0, 1, 0, 1});
                f.resize(9);
                c.send_bytes(f);
                std::this_thread::sleep_for(std::chrono::milliseconds(300));
                c.close();
            }
        });
    }
    for (int i = 0; i < 2; ++i) {
        threads.emplace_back([&] {
            test::ModbusTcpClient c;
            while (!stop) {
                if (!c.connected()) c.connect(config.port);
                c.request({6, 0, 0, 0, 7}, 2000);
                c.request({5, 0, 5, 0xFF, 0}, 2000);
                std::this_thread::sleep_for(std::chrono::milliseconds(100));
            }
        });
    }
    std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
    stop = true;
    for (auto& t : threads) t.join();

    std::sort(latencies_ms.begin(), latencies_ms.end());
    if (latencies_ms.empty()) {
        std::printf("no answers\n");
        return 1;
    }
    auto at = [&](double q) {
        return latencies_ms[static_cast<std::size_t>(q *
                                                     static_cast<double>(latencies_ms.size() - 1))];
    };
    std::printf("modbus latency under load (%.0f s): %zu requests answered, %d lost\n", seconds,
                latencies_ms.size(), lost.load());
    std::printf("p50 %.3f ms  p99 %.3f ms  max %.3f ms  (target p99 < 5 ms)\n", at(0.5), at(0.99),
                latencies_ms.back());
    return 0;
}
