#include "factory/KeyScript.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace factory {

namespace {
[[noreturn]] void bad(const std::string& token, const std::string& why) {
    throw std::invalid_argument("factory::parseKeyScript(): '" + token + "': " + why);
}

// The N of "*N" (1 without it).
int repeat(const std::string& token, const std::string& tail) {
    if (tail.empty()) return 1;
    errno = 0;
    char* end = nullptr;
    const long n = std::strtol(tail.c_str() + 1, &end, 10);
    if (tail[0] != '*' || tail.size() < 2 || *end != '\0' || errno == ERANGE || n < 1 || n > 100000)
        bad(token, "expected *N with N from 1 to 100000 after the key");
    return int(n);
}

double number(const std::string& token, const std::string& v, const char* form) {
    errno = 0;
    char* end = nullptr;
    const double x = std::strtod(v.c_str(), &end);
    if (v.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(x)) bad(token, form);
    return x;
}
}  // namespace

std::vector<ScriptFrame> parseKeyScript(const std::string& text) {
    std::vector<ScriptFrame> out;
    std::istringstream in(text);
    std::string token;
    while (in >> token) {
        std::string up = token;
        std::transform(up.begin(), up.end(), up.begin(), [](unsigned char c) { return char(std::toupper(c)); });
        const bool drag = up.rfind("DRAG:", 0) == 0, click = up.rfind("CLICK:", 0) == 0;
        if (drag || click) {
            const std::string v = token.substr(drag ? 5 : 6);
            const size_t comma = v.find(',');
            const char* form = drag ? "expected drag:DX,DY" : "expected click:X,Y";
            if (comma == std::string::npos) bad(token, form);
            ScriptFrame f;
            (drag ? f.dragX : f.clickX) = number(token, v.substr(0, comma), form);
            (drag ? f.dragY : f.clickY) = number(token, v.substr(comma + 1), form);
            f.click = click;
            out.push_back(f);
            continue;
        }
        const size_t star = up.find('*');
        const std::string name = up.substr(0, star), tail = star == std::string::npos ? "" : up.substr(star);
        const int n = repeat(token, tail);
        if (name == "WAIT") {
            out.resize(out.size() + size_t(n));
            continue;
        }
        static const std::pair<const char*, Key> kNames[] = {
            {"W", Key::Forward},      {"S", Key::Back},    {"A", Key::Left},      {"D", Key::Right},
            {"F", Key::FlyWalk},      {"M", Key::LodMode}, {"O", Key::Occlusion}, {"P", Key::Screenshot},
            {"F12", Key::Screenshot}, {"H", Key::Overlay}, {"ESC", Key::Quit},
        };
        const auto* it =
            std::find_if(std::begin(kNames), std::end(kNames), [&](const auto& k) { return name == k.first; });
        if (it == std::end(kNames))
            bad(token, "not a key (W A S D F M O P F12 H Esc), drag:DX,DY, click:X,Y or wait*N");
        const size_t first = out.size();
        out.resize(first + size_t(n));
        const Key k = it->second;
        const bool moves = k == Key::Forward || k == Key::Back || k == Key::Left || k == Key::Right;
        if (!moves) out[first].pressed.push_back(k);
        for (size_t i = first; i < out.size(); ++i) {
            out[i].forward = k == Key::Forward;
            out[i].back = k == Key::Back;
            out[i].left = k == Key::Left;
            out[i].right = k == Key::Right;
        }
    }
    return out;
}

}  // namespace factory
