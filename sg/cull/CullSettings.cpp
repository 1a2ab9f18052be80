#include "sg/cull/CullSettings.h"

#include <string>

namespace sg {

namespace {
bool powerOfTwoMapSize(int v) { return v >= 8 && v <= 1024 && (v & (v - 1)) == 0; }
}  // namespace

void OcclusionSettings::validate(const char* caller) const {
    const SettingCheck c{caller};
    c.member("occlusion.mode", mode, OcclusionMode::Adaptive);
    c.member("occlusion.method", method, OcclusionMethod::Auto);
    c.share("occlusion.autoMapShare", autoMapShare);
    c.atLeast("occlusion.minOccluderPixels", minOccluderPixels, 0.0);
    c.share("occlusion.adaptiveMinGain", adaptiveMinGain);
    if (!powerOfTwoMapSize(homWidth))
        c.fail("occlusion.homWidth", settingValue((long long)homWidth), "a power of two in 8..1024");
    if (!powerOfTwoMapSize(homHeight))
        c.fail("occlusion.homHeight", settingValue((long long)homHeight), "a power of two in 8..1024");
    if (!(homOpacity > 0.0 && homOpacity <= 1.0)) c.fail("occlusion.homOpacity", settingValue(homOpacity), "in (0, 1]");
    c.range("occlusion.homObbLevels", homObbLevels, 0, 16);
    c.member("occlusion.measureOnly.cap", measureOnly.cap, OccluderCap::CenterPlane);
    c.range("occlusion.measureOnly.screenSplits", measureOnly.screenSplits, 0, 8);
}

void CullSettings::validate(const char* caller) const {
    const SettingCheck c{caller};
    c.member("strategy", strategy, CullStrategy::CenterBox);
    c.atLeast("smallFeaturePixels", smallFeaturePixels, 0.0);
    if (!(lodHysteresis >= 0.0 && lodHysteresis < 1.0))
        c.fail("lodHysteresis", settingValue(lodHysteresis), "in [0, 1)");
    c.positive("lodScale", lodScale);
    c.range("screenRectTriangles", screenRectTriangles, 1, 65536);
    c.range("measureOnly.frustumPlanes", measureOnly.frustumPlanes, 0, 0x3f);
    occlusion.validate(caller);
    if (lodBudget.enabled) lodBudget.validate(caller);
}

namespace {
const EnumName<CullStrategy> kStrategies[] = {{CullStrategy::None, "none"},
                                              {CullStrategy::Sphere, "sphere"},
                                              {CullStrategy::Aabb, "aabb"},
                                              {CullStrategy::SphereSphere, "sphere-sphere"},
                                              {CullStrategy::CenterBox, "center-box"}};
const EnumName<OcclusionMode> kOcclusionModes[] = {
    {OcclusionMode::Off, "off"}, {OcclusionMode::EveryFrame, "every-frame"}, {OcclusionMode::Adaptive, "adaptive"}};
const EnumName<OcclusionMethod> kOcclusionMethods[] = {
    {OcclusionMethod::Tree, "tree"}, {OcclusionMethod::Hom, "hom"}, {OcclusionMethod::Auto, "auto"}};
}  // namespace

const char* strategyName(CullStrategy s) { return enumName(kStrategies, s); }
CullStrategy parseStrategy(const std::string& name) {
    return parseEnum(kStrategies, name, "parseStrategy()", "a cull strategy");
}

bool isConservative(CullStrategy s) { return s != CullStrategy::CenterBox; }

const char* occlusionModeName(OcclusionMode m) { return enumName(kOcclusionModes, m); }
OcclusionMode parseOcclusionMode(const std::string& name) {
    // The names before OcclusionMethod took "tree" and "auto": scripts written then keep working.
    if (name == "tree") return OcclusionMode::EveryFrame;
    if (name == "auto") return OcclusionMode::Adaptive;
    return parseEnum(kOcclusionModes, name, "parseOcclusionMode()", "an occlusion mode");
}

const char* occlusionMethodName(OcclusionMethod m) { return enumName(kOcclusionMethods, m); }
OcclusionMethod parseOcclusionMethod(const std::string& name) {
    return parseEnum(kOcclusionMethods, name, "parseOcclusionMethod()", "an occlusion method");
}

}  // namespace sg
