#include "daemon/modbus/register_image.hpp"

#include <algorithm>
#include <bit>
#include <limits>

#include "daemon/modbus/register_words.hpp"

namespace tlsmon {

namespace {

void put(std::vector<std::uint16_t>& regs, int address, std::array<std::uint16_t, 2> words) {
    regs.at(static_cast<std::size_t>(address)) = words[0];
    regs.at(static_cast<std::size_t>(address) + 1) = words[1];
}

float as_float(const std::optional<double>& v) {
    return v ? static_cast<float>(*v) : std::numeric_limits<float>::quiet_NaN();
}

int block(int zone_slot, int quantity_slot) {
    return kRegZoneBase + zone_slot * kRegZoneStride + quantity_slot * kRegQuantityStride;
}

}  // namespace

RegisterImage render_registers(const RegisterMap& map, const MapInputs& inputs,
                               const ModbusSnapshot& s, WordOrder order) {
    RegisterImage img;
    img.input_registers.assign(static_cast<std::size_t>(map.input_registers), 0);
    img.discrete_inputs.assign(static_cast<std::size_t>(map.discrete_inputs), 0);
    img.coil_rules.assign(static_cast<std::size_t>(map.coils), "");
    auto& r = img.input_registers;

    bool any_alarm = false, any_unack = false;
    for (const auto& rule : s.rules) {
        if (rule.level != AlarmLevel::none) any_alarm = true;
        if (unacknowledged(rule.state)) any_unack = true;
    }
    std::uint16_t status = kStatusRunning;
    if (s.database_ok) status |= kStatusDatabaseOk;
    if (s.backlog) status |= kStatusBacklog;
    if (s.last_epoch_failed) status |= kStatusLastEpochFailed;
    if (s.stale) status |= kStatusStale;
    if (any_alarm) status |= kStatusAnyAlarm;
    if (s.disk_full) status |= kStatusDiskFull;
    r.at(kRegMapVersion) = kModbusMapVersion;
    r.at(kRegStatus) = status;
    put(r, kRegLastEpochTime, u32_words(s.last_epoch_time, order));
    put(r, kRegEpochsProcessed, u32_words(s.epochs_processed, order));
    put(r, kRegTestFloat, float_words(123456.0f, order));

    // A zone quantity's value, LoD and rate: float32, or int32 in the quantity's fixed unit.
    const bool integer = inputs.value_type == ModbusValueType::int32;
    const auto words = [&](const std::optional<double>& v, std::size_t quantity_slot) {
        if (!integer) return float_words(as_float(v), order);
        const Int32Scale scale = int32_scale(inputs.quantities.at(quantity_slot));
        return u32_words(std::bit_cast<std::uint32_t>(int32_value(v, scale)), order);
    };
    const auto nan = integer ? u32_words(std::bit_cast<std::uint32_t>(kInt32None), order)
                             : float_words(std::numeric_limits<float>::quiet_NaN(), order);
    for (const auto& z : inputs.zones) {
        for (std::size_t q = 0; q < inputs.quantities.size(); ++q) {
            const int b = block(z.slot, static_cast<int>(q));
            put(r, b + kOffValue, nan);
            put(r, b + kOffLod, nan);
            put(r, b + kOffRate, nan);
        }
    }
    for (const auto& v : s.values) {
        const int b = block(v.zone_slot, v.quantity_slot);
        if (b + kOffState >= static_cast<int>(r.size())) continue;  // not in this map
        const auto slot = static_cast<std::size_t>(v.quantity_slot);
        put(r, b + kOffValue, words(v.value, slot));
        put(r, b + kOffLod, words(v.lod, slot));
        put(r, b + kOffRate, words(v.rate, slot));
        std::uint16_t quality = 0;
        if (v.value && (!integer || words(v.value, slot) != nan)) quality |= kQualityValid;
        if (v.stale) quality |= kQualityStale;
        if (v.value && !v.significant) quality |= kQualityBelowLod;
        if (v.registration_degraded) quality |= kQualityRegistrationDegraded;
        if (v.unregistered) quality |= kQualityUnregistered;
        r.at(static_cast<std::size_t>(b + kOffQuality)) = quality;
    }
    // Each zone quantity shows the highest level among the rules watching it, and that rule's
    // state; with no rule at a level, the "worst" state (unacknowledged first).
    for (const auto& rule : s.rules) {
        const auto z = std::find_if(inputs.zones.begin(), inputs.zones.end(),
                                    [&](const MapSlot& m) { return m.name == rule.zone; });
        const auto q = std::find(inputs.quantities.begin(), inputs.quantities.end(), rule.quantity);
        if (z != inputs.zones.end() && q != inputs.quantities.end()) {
            const int b = block(z->slot, static_cast<int>(q - inputs.quantities.begin()));
            auto& level = r.at(static_cast<std::size_t>(b + kOffLevel));
            auto& state = r.at(static_cast<std::size_t>(b + kOffState));
            const std::uint16_t l = alarm_level_code(rule.level);
            const std::uint16_t st = isa_state_code(rule.state);
            const std::uint16_t unack = isa_state_code(IsaState::unack);
            if (l > level || (l == level && unacknowledged(rule.state) && state != unack)) {
                level = l;
                state = st;
            }
        }
        const int bit = kBitRuleBase + rule.slot * kBitRuleStride;
        if (bit + 3 >= static_cast<int>(img.discrete_inputs.size())) continue;
        const std::uint16_t l = alarm_level_code(rule.level);
        for (int level = 1; level <= 3; ++level) {
            img.discrete_inputs[static_cast<std::size_t>(bit + level - 1)] =
                (l >= level && l <= 3) ? 1 : 0;
        }
        img.discrete_inputs[static_cast<std::size_t>(bit + 3)] = unacknowledged(rule.state) ? 1 : 0;
    }
    img.discrete_inputs.at(kBitAnyAlarm) = any_alarm ? 1 : 0;
    img.discrete_inputs.at(kBitAnyUnacknowledged) = any_unack ? 1 : 0;
    img.discrete_inputs.at(kBitSystemFault) =
        (!s.database_ok || s.last_epoch_failed || s.disk_full) ? 1 : 0;
    img.coil_rules.at(kCoilAcknowledgeAll) = "*";
    for (const auto& rule : inputs.rules) {
        const auto c = static_cast<std::size_t>(kCoilRuleBase + rule.slot);
        if (c < img.coil_rules.size()) img.coil_rules[c] = rule.name;
    }
    return img;
}

}  // namespace tlsmon
