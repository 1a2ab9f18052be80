// Json: one flat JSON object, keys in insertion order, or the same fields as a table.
#pragma once
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

namespace osgbench {

class Json {
public:
    Json& add(const std::string& k, double v, int decimals = 4) {
        char buf[64];
        if (!std::isfinite(v))
            std::snprintf(buf, sizeof buf, "null");
        else
            std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
        kv_.emplace_back(k, buf);
        return *this;
    }
    Json& addInt(const std::string& k, long long v) {
        kv_.emplace_back(k, std::to_string(v));
        return *this;
    }
    Json& addBool(const std::string& k, bool v) {
        kv_.emplace_back(k, v ? "true" : "false");
        return *this;
    }
    Json& addStr(const std::string& k, const std::string& v) {
        kv_.emplace_back(k, "\"" + v + "\"");
        return *this;
    }
    std::string str() const {
        std::string s = "{";
        for (size_t i = 0; i < kv_.size(); ++i) s += (i ? ",\"" : "\"") + kv_[i].first + "\":" + kv_[i].second;
        return s + "}";
    }
    const std::vector<std::pair<std::string, std::string>>& fields() const { return kv_; }

private:
    std::vector<std::pair<std::string, std::string>> kv_;
};

}  // namespace osgbench
