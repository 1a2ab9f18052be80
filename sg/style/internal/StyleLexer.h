// The styling language's tokens: numbers, quoted strings, ${property} references, names and operators.
#pragma once
#include "sg/style/internal/StyleProgram.h"

#include <cstdint>
#include <string>
#include <vector>

namespace sg::style {

enum class TokenKind : uint8_t { End, Number, String, Var, Ident, Punct };

struct Token {
    TokenKind kind;
    uint32_t pos;      // of its first character
    std::string text;  // a String's value, a Var's property name, an Ident's or Punct's spelling
    double number;
};

// The tokens of p.text, ending with End at the text's length; StyleError at a character that starts none.
std::vector<Token> lexProgram(const Program& p);

}  // namespace sg::style
