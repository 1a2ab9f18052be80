#include "sg/core/Settings.h"

#include <cmath>
#include <cstdio>

namespace sg {

SettingError::SettingError(const std::string& caller, std::string setting, const std::string& value,
                           const std::string& allowed)
    : std::invalid_argument(caller + ": " + setting + " " + value + " is not " + allowed),
      setting_(std::move(setting)) {}

std::string settingValue(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%g", v);
    return b;
}
std::string settingValue(long long v) { return std::to_string(v); }

void SettingCheck::atLeast(const char* name, double v, double lo) const {
    if (!(v >= lo && std::isfinite(v))) fail(name, settingValue(v), "a finite number >= " + settingValue(lo));
}
void SettingCheck::positive(const char* name, double v) const {
    if (!(v > 0.0 && std::isfinite(v))) fail(name, settingValue(v), "a finite number > 0");
}
void SettingCheck::share(const char* name, double v) const {
    if (!(v >= 0.0 && v <= 1.0)) fail(name, settingValue(v), "in [0, 1]");
}
void SettingCheck::range(const char* name, long long v, long long lo, long long hi) const {
    if (v < lo || v > hi) fail(name, settingValue(v), "in " + settingValue(lo) + ".." + settingValue(hi));
}
void SettingCheck::fail(const char* name, const std::string& v, const std::string& allowed) const {
    throw SettingError(caller, name, v, allowed);
}

std::string unknownName(const char* caller, const std::string& name, const char* what, const char* const* names,
                        size_t count) {
    std::string list;
    for (size_t i = 0; i < count; ++i) list += (i ? ", " : "") + std::string(names[i]);
    return std::string(caller) + ": '" + name + "' is not " + what + " (" + list + ")";
}

}  // namespace sg
