// A parsed style expression: its syntax tree in one flat array, shared by the parser, the evaluator and the
// built-in functions.
#pragma once
#include "sg/style/StyleExpression.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace sg::style {

enum class Op : uint8_t {
    Const,  // constants[value]
    Ref,    // ${name}: names[value], read through slot (or define)
    Neg,
    Plus,
    Not,
    Add,
    Sub,
    Mul,
    Div,
    Mod,
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
    And,
    Or,
    Match,
    NoMatch,
    Cond,    // a ? b : c
    Call,    // fn over args[firstArg, firstArg + argCount); a method's receiver is its first argument
    Member,  // a.x: component `value` of a vector
    Index,   // a[b]
};

enum class Fn : uint8_t {
    Color,
    Rgb,
    Rgba,
    Hsl,
    Hsla,
    Vec2,
    Vec3,
    Vec4,
    RegExp,
    IsNaN,
    IsFinite,
    Number,
    String,
    Boolean,
    // component-wise over a number or vector
    Abs,
    Sqrt,
    Floor,
    Ceil,
    Round,
    Sign,
    Fract,
    Exp,
    Log,
    Exp2,
    Log2,
    Cos,
    Sin,
    Tan,
    Acos,
    Asin,
    Atan,
    Radians,
    Degrees,
    Min,
    Max,
    Pow,
    Atan2,
    Clamp,
    Mix,
    Length,
    Distance,
    Dot,
    Cross,
    Normalize,
    Test,
    Exec,
    ToString,  // methods
};

struct Node {
    Op op = Op::Const;
    Fn fn = Fn::Color;
    uint16_t height = 1;  // of the subtree: bounds the evaluator's recursion
    uint32_t pos = 0;     // in the text: where an error in this node is reported
    int a = -1, b = -1, c = -1;
    int firstArg = 0, argCount = 0;
    int value = -1;
    int slot = -1;                            // Ref: the feature's slot
    const StyleExpression* define = nullptr;  // Ref: the define it names, evaluated in its place
};

struct Program {
    std::string text;
    std::vector<Node> nodes;
    std::vector<int> args;
    std::vector<StyleValue> constants;
    std::vector<std::string> names;
    int root = -1;

    [[noreturn]] void fail(uint32_t pos, const std::string& reason) const { throw StyleError(text, pos, reason); }
};

// Deeper trees are refused when parsed: the evaluator recurses once a level.
constexpr int kMaxHeight = 200;

// What the evaluator reads a reference through: a feature's slots, or names.
struct EvalContext {
    const StyleFeature* feature = nullptr;
    const StyleLookup* lookup = nullptr;
};

void parseProgram(Program& p);  // p.text to the tree; StyleError on a mistake
StyleValue evaluateNode(const Program& p, int node, const EvalContext& ctx);

struct FunctionInfo {
    const char* name;
    Fn fn;
    int minArgs, maxArgs;  // a method's counts include its receiver
};
const FunctionInfo* findFunction(const std::string& name);
const FunctionInfo* findMethod(const std::string& name);
// Fn over `n` evaluated arguments; errors reported at `pos`.
StyleValue callFunction(const Program& p, uint32_t pos, Fn fn, StyleValue* args, int n);
// regExp(pattern, flags) compiled (ECMAScript); a bad pattern or flag a StyleError at pos.
std::shared_ptr<const StyleRegExp> compileRegExp(const Program& p, uint32_t pos, const std::string& pattern,
                                                 const std::string& flags);

}  // namespace sg::style
