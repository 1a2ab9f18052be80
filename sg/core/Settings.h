// Settings checked where they are set: SettingError names the entry point, the setting, its value and what is
// allowed, and SettingCheck holds the checks every settings struct makes.
#pragma once
#include <cstdint>
#include <stdexcept>
#include <string>

namespace sg {

// A setting out of its range: the message names the entry point, the setting, its value and what is allowed.
class SettingError : public std::invalid_argument {
public:
    SettingError(const std::string& caller, std::string setting, const std::string& value, const std::string& allowed);
    const std::string& setting() const { return setting_; }

private:
    std::string setting_;
};

// A value as a setting's message shows it ("%g" for a double).
std::string settingValue(double v);
std::string settingValue(long long v);

// Each check throws SettingError(caller, name, value, allowed) unless the value is allowed.
struct SettingCheck {
    const char* caller;
    void atLeast(const char* name, double v, double lo) const;
    void positive(const char* name, double v) const;
    void share(const char* name, double v) const;  // in [0, 1]
    void range(const char* name, long long v, long long lo, long long hi) const;
    template <class E>
    void member(const char* name, E v, E last) const {
        if (uint32_t(v) > uint32_t(last)) fail(name, settingValue((long long)v), "one of the enumeration's values");
    }
    [[noreturn]] void fail(const char* name, const std::string& v, const std::string& allowed) const;
};

}  // namespace sg
