// Settings checked where they are set: SettingError names the entry point, the setting, its value and what is
// allowed, and SettingCheck holds the checks every settings struct makes.
#pragma once
#include <cstddef>
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

// An enumeration's names: one table per enumeration, read both ways, with one wording for a name that is not
// one of them.
template <class E>
struct EnumName {
    E value;
    const char* name;
};

template <class E, size_t N>
const char* enumName(const EnumName<E> (&names)[N], E v) {
    for (const EnumName<E>& n : names)
        if (n.value == v) return n.name;
    return "?";
}

// The message of an unknown name: "<caller>: '<name>' is not <what> (<a>, <b>, ...)".
std::string unknownName(const char* caller, const std::string& name, const char* what, const char* const* names,
                        size_t count);

// The value named `name`; throws std::invalid_argument with unknownName's message.
template <class E, size_t N>
E parseEnum(const EnumName<E> (&names)[N], const std::string& name, const char* caller, const char* what) {
    for (const EnumName<E>& n : names)
        if (name == n.name) return n.value;
    const char* all[N];  // the names listed only when the name is unknown
    for (size_t i = 0; i < N; ++i) all[i] = names[i].name;
    throw std::invalid_argument(unknownName(caller, name, what, all, N));
}

}  // namespace sg
