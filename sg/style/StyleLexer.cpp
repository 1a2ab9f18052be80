#include "sg/style/internal/StyleLexer.h"

#include <cctype>
#include <cstdlib>
#include <cstring>

namespace sg::style {

namespace {

bool identStart(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_' || c == '$'; }
bool identPart(char c) { return identStart(c) || std::isdigit(static_cast<unsigned char>(c)); }
bool digit(char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; }

void appendUtf8(std::string& s, uint32_t cp) {
    if (cp < 0x80) {
        s += char(cp);
    } else if (cp < 0x800) {
        s += char(0xC0 | (cp >> 6));
        s += char(0x80 | (cp & 0x3F));
    } else {
        s += char(0xE0 | (cp >> 12));
        s += char(0x80 | ((cp >> 6) & 0x3F));
        s += char(0x80 | (cp & 0x3F));
    }
}

class Lexer {
public:
    explicit Lexer(const Program& p) : p_(p), t_(p.text) {}

    std::vector<Token> run() {
        std::vector<Token> out;
        for (;;) {
            while (i_ < t_.size() && std::isspace(static_cast<unsigned char>(t_[i_]))) ++i_;
            if (i_ >= t_.size()) break;
            out.push_back(next());
        }
        out.push_back(Token{TokenKind::End, uint32_t(t_.size()), "", 0.0});
        return out;
    }

private:
    Token next() {
        const uint32_t start = uint32_t(i_);
        const char c = t_[i_];
        if (digit(c) || (c == '.' && i_ + 1 < t_.size() && digit(t_[i_ + 1]))) return number(start);
        if (c == '\'' || c == '"') return Token{TokenKind::String, start, quoted(), 0.0};
        if (c == '$' && i_ + 1 < t_.size() && t_[i_ + 1] == '{') return variable(start);
        if (identStart(c)) {
            while (i_ < t_.size() && identPart(t_[i_])) ++i_;
            return Token{TokenKind::Ident, start, t_.substr(start, i_ - start), 0.0};
        }
        if (c == '`') p_.fail(start, "template strings (`...`) are not supported");
        return punct(start);
    }

    Token number(uint32_t start) {
        while (i_ < t_.size() && digit(t_[i_])) ++i_;
        if (i_ < t_.size() && t_[i_] == '.') {
            ++i_;
            while (i_ < t_.size() && digit(t_[i_])) ++i_;
        }
        if (i_ < t_.size() && (t_[i_] == 'e' || t_[i_] == 'E')) {
            size_t j = i_ + 1;
            if (j < t_.size() && (t_[j] == '+' || t_[j] == '-')) ++j;
            if (j >= t_.size() || !digit(t_[j])) p_.fail(uint32_t(i_), "expected the exponent's digits");
            i_ = j;
            while (i_ < t_.size() && digit(t_[i_])) ++i_;
        }
        if (i_ < t_.size() && identStart(t_[i_])) p_.fail(uint32_t(i_), "unexpected character after a number");
        const std::string s = t_.substr(start, i_ - start);
        return Token{TokenKind::Number, start, s, std::strtod(s.c_str(), nullptr)};
    }

    // A string in ' or " with JavaScript's escapes; i_ at the opening quote, left after the closing one.
    std::string quoted() {
        const size_t start = i_;
        const char q = t_[i_++];
        std::string s;
        while (i_ < t_.size() && t_[i_] != q) {
            char c = t_[i_++];
            if (c != '\\') {
                s += c;
                continue;
            }
            if (i_ >= t_.size()) break;
            c = t_[i_++];
            switch (c) {
                case 'n': s += '\n'; break;
                case 't': s += '\t'; break;
                case 'r': s += '\r'; break;
                case 'b': s += '\b'; break;
                case 'f': s += '\f'; break;
                case 'v': s += '\v'; break;
                case '0': s += '\0'; break;
                case 'x': s += char(hex(2)); break;
                case 'u': appendUtf8(s, hex(4)); break;
                default: s += c; break;  // \\ \' \" and any other character as itself
            }
        }
        if (i_ >= t_.size()) p_.fail(uint32_t(start), "unterminated string");
        ++i_;
        return s;
    }

    uint32_t hex(int digits) {
        if (i_ + size_t(digits) > t_.size())
            p_.fail(uint32_t(i_), "expected " + std::to_string(digits) + " hex digits");
        uint32_t v = 0;
        for (int k = 0; k < digits; ++k, ++i_) {
            const char c = char(std::tolower(static_cast<unsigned char>(t_[i_])));
            if (!std::isxdigit(static_cast<unsigned char>(c))) p_.fail(uint32_t(i_), "expected a hex digit");
            v = v * 16 + uint32_t(digit(c) ? c - '0' : c - 'a' + 10);
        }
        return v;
    }

    // ${name}, ${feature}, ${feature.name}, ${feature['name']}: the token's text is the property's name.
    Token variable(uint32_t start) {
        i_ += 2;
        std::string name;
        if (t_.compare(i_, 8, "feature[") == 0) {
            i_ += 8;
            if (i_ >= t_.size() || (t_[i_] != '\'' && t_[i_] != '"'))
                p_.fail(uint32_t(i_), "expected a quoted name in ${feature[...]}");
            name = quoted();
            if (t_.compare(i_, 2, "]}") != 0) p_.fail(uint32_t(i_), "expected ']}'");
            i_ += 2;
        } else {
            const size_t end = t_.find('}', i_);
            if (end == std::string::npos) p_.fail(start, "unterminated ${");
            name = t_.substr(i_, end - i_);
            if (name.compare(0, 8, "feature.") == 0) name.erase(0, 8);
            i_ = end + 1;
        }
        if (name.empty()) p_.fail(start, "empty property name");
        return Token{TokenKind::Var, start, name, 0.0};
    }

    Token punct(uint32_t start) {
        static const char* const kOps[] = {"===", "!==", "==", "!=", "<=", ">=", "&&", "||", "=~", "!~"};
        for (const char* op : kOps) {
            const size_t n = std::strlen(op);
            if (t_.compare(i_, n, op) != 0) continue;
            if (n == 2 && (op[1] == '=' && (op[0] == '=' || op[0] == '!')))
                p_.fail(start, std::string("'") + op + "' is not supported: use '" + op + "='");
            i_ += n;
            return Token{TokenKind::Punct, start, op, 0.0};
        }
        const char c = t_[i_];
        if (!std::strchr("!<>+-*/%?:(),.[]", c)) p_.fail(start, std::string("unexpected character '") + c + "'");
        ++i_;
        return Token{TokenKind::Punct, start, std::string(1, c), 0.0};
    }

    const Program& p_;
    const std::string& t_;
    size_t i_ = 0;
};

}  // namespace

std::vector<Token> lexProgram(const Program& p) { return Lexer(p).run(); }

}  // namespace sg::style
