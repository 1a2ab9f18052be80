// The disk cache's freshness rules (RFC 9111) against times worked out by hand. Dates in seconds since the epoch:
// "Sun, 06 Nov 1994 08:49:37 GMT" is 784111777.
#include "loaders/net/internal/HttpCachePolicy.h"

#include <gtest/gtest.h>

using namespace sg;
using namespace sg::net;

namespace {

constexpr int64_t kDate = 784111777;  // Sun, 06 Nov 1994 08:49:37 GMT
const char* const kDateText = "Sun, 06 Nov 1994 08:49:37 GMT";

}  // namespace

TEST(HttpCachePolicy, ParsesCacheControl) {
    const CacheControl cc = parseCacheControl("public, MAX-AGE=600, s-maxage=60, must-revalidate");
    ASSERT_TRUE(cc.maxAge.has_value());
    EXPECT_EQ(*cc.maxAge, 600);  // s-maxage is a shared cache's
    EXPECT_TRUE(cc.mustRevalidate);
    EXPECT_FALSE(cc.noStore);
    EXPECT_FALSE(cc.noCache);
    EXPECT_TRUE(parseCacheControl("no-store").noStore);
    EXPECT_TRUE(parseCacheControl("private, no-cache=\"set-cookie, x\"").noCache);
    EXPECT_EQ(parseCacheControl("max-age=\"30\"").maxAge.value_or(-1), 30);
    EXPECT_FALSE(parseCacheControl("max-age=ten").maxAge.has_value());  // not a number: none
    EXPECT_FALSE(parseCacheControl("max-age=-5").maxAge.has_value());
    EXPECT_EQ(parseCacheControl("max-age=99999999999999999999").maxAge.value_or(-1), int64_t(1) << 31);
}

TEST(HttpCachePolicy, ParsesTheThreeDateForms) {
    EXPECT_EQ(parseHttpDate(kDateText).value_or(-1), kDate);
    EXPECT_EQ(parseHttpDate("Sunday, 06-Nov-94 08:49:37 GMT").value_or(-1), kDate);
    EXPECT_EQ(parseHttpDate("Sun Nov  6 08:49:37 1994").value_or(-1), kDate);
    EXPECT_FALSE(parseHttpDate("0").has_value());
    EXPECT_FALSE(parseHttpDate("").has_value());
}

TEST(HttpCachePolicy, MaxAgeWinsOverExpires) {
    const HttpHeaders h = {{"date", kDateText},
                           {"cache-control", "max-age=100"},
                           {"expires", "Sun, 06 Nov 1994 08:59:37 GMT"}};  // Date + 600
    EXPECT_EQ(freshnessLifetime(h, kDate), 100);
    EXPECT_TRUE(isFresh(h, kDate, kDate + 99));
    EXPECT_FALSE(isFresh(h, kDate, kDate + 100));
}

TEST(HttpCachePolicy, ExpiresCountsFromDateNotFromTheClock) {
    // The server's clock is 1000 s behind ours: Expires less Date is the lifetime, whatever our clock says.
    const HttpHeaders h = {{"date", kDateText}, {"expires", "Sun, 06 Nov 1994 08:59:37 GMT"}};
    EXPECT_EQ(freshnessLifetime(h, kDate + 1000), 600);
    // Received at kDate + 1000: an apparent age of 1000 s already, past the 600.
    EXPECT_FALSE(isFresh(h, kDate + 1000, kDate + 1000));
    // Received when sent: fresh until 600 s later.
    EXPECT_TRUE(isFresh(h, kDate, kDate + 599));
    EXPECT_FALSE(isFresh(h, kDate, kDate + 600));
    // No Date: the time it was received stands for it.
    EXPECT_EQ(freshnessLifetime({{"expires", "Sun, 06 Nov 1994 08:59:37 GMT"}}, kDate + 100), 500);
    // An Expires that is not a date means already expired.
    EXPECT_EQ(freshnessLifetime({{"date", kDateText}, {"expires", "0"}}, kDate), 0);
}

TEST(HttpCachePolicy, AgeAddsToTheTimeSinceReceived) {
    const HttpHeaders h = {{"date", kDateText}, {"cache-control", "max-age=100"}, {"age", "60"}};
    EXPECT_EQ(currentAge(h, kDate, kDate), 60);
    EXPECT_EQ(currentAge(h, kDate, kDate + 30), 90);
    EXPECT_TRUE(isFresh(h, kDate, kDate + 39));
    EXPECT_FALSE(isFresh(h, kDate, kDate + 40));
    // Date 10 s behind the time received, no Age: 10 s old when received.
    EXPECT_EQ(currentAge({{"date", kDateText}}, kDate + 10, kDate + 15), 15);
    // Our clock behind the server's: no negative age.
    EXPECT_EQ(currentAge({{"date", kDateText}}, kDate - 50, kDate - 50), 0);
}

TEST(HttpCachePolicy, HeuristicIsATenthOfTheTimeSinceModified) {
    const HttpHeaders h = {{"date", kDateText}, {"last-modified", "Sat, 05 Nov 1994 08:49:37 GMT"}};  // a day before
    EXPECT_EQ(freshnessLifetime(h, kDate), 8640);
    EXPECT_TRUE(isFresh(h, kDate, kDate + 8639));
    EXPECT_FALSE(isFresh(h, kDate, kDate + 8640));
    EXPECT_EQ(freshnessLifetime({{"date", kDateText}}, kDate), 0);  // nothing to go by: stale at once
}

TEST(HttpCachePolicy, NoCacheIsNeverFresh) {
    const HttpHeaders h = {{"date", kDateText}, {"cache-control", "no-cache, max-age=1000"}, {"etag", "\"a\""}};
    EXPECT_FALSE(isFresh(h, kDate, kDate));
    EXPECT_TRUE(storable(200, h, kDate));
}

TEST(HttpCachePolicy, WhatIsStored) {
    const HttpHeaders fresh = {{"date", kDateText}, {"cache-control", "max-age=60"}};
    EXPECT_TRUE(storable(200, fresh, kDate));
    EXPECT_FALSE(storable(206, fresh, kDate));
    EXPECT_FALSE(storable(200, {{"cache-control", "max-age=60, no-store"}}, kDate));
    EXPECT_FALSE(storable(200, {{"cache-control", "max-age=60"}, {"vary", "Accept-Language, *"}}, kDate));
    EXPECT_TRUE(storable(200, {{"cache-control", "max-age=60"}, {"vary", "Accept-Language"}}, kDate));
    // Stale at once and no validator: it could never be used.
    EXPECT_FALSE(storable(200, {{"date", kDateText}, {"cache-control", "max-age=0"}}, kDate));
    EXPECT_TRUE(storable(200, {{"date", kDateText}, {"cache-control", "max-age=0"}, {"etag", "\"1\""}}, kDate));
    EXPECT_TRUE(storable(200, {{"last-modified", kDateText}}, kDate));
}

TEST(HttpCachePolicy, RevalidatesWithTheValidators) {
    EXPECT_EQ(conditionalHeaders({{"etag", "\"v1\""}}), std::vector<std::string>{"If-None-Match: \"v1\""});
    EXPECT_EQ(conditionalHeaders({{"last-modified", kDateText}}),
              std::vector<std::string>{std::string("If-Modified-Since: ") + kDateText});
    EXPECT_EQ(conditionalHeaders({{"etag", "W/\"v\""}, {"last-modified", kDateText}}).size(), 2u);
    EXPECT_TRUE(conditionalHeaders({{"cache-control", "max-age=1"}}).empty());
}

TEST(HttpCachePolicy, A304UpdatesTheStoredHeaders) {
    const HttpHeaders stored = {{"cache-control", "max-age=10"}, {"date", kDateText}, {"age", "5"}, {"etag", "\"1\""}};
    const HttpHeaders got = {{"cache-control", "max-age=20"}, {"server", "x"}};
    const HttpHeaders h = refreshedHeaders(stored, got);
    EXPECT_EQ(headerValue(h, "cache-control"), "max-age=20");
    EXPECT_EQ(headerValue(h, "etag"), "\"1\"");
    EXPECT_EQ(headerValue(h, "date"), "");  // the old Date and Age would age the refreshed entry
    EXPECT_EQ(headerValue(h, "age"), "");
    EXPECT_EQ(headerValue(h, "server"), "");  // not a header the cache keeps
    EXPECT_TRUE(isFresh(h, kDate + 1000, kDate + 1019));
}

TEST(HttpCachePolicy, VaryKeysOnTheRequestsHeaders) {
    const HttpHeaders h = {{"vary", "Accept-Language, X-Key"}};
    EXPECT_EQ(varyKey(h, {"accept-language:  fr ", "Authorization: a"}), "accept-language: fr\nx-key: \n");
    EXPECT_NE(varyKey(h, {"Accept-Language: fr"}), varyKey(h, {"Accept-Language: de"}));
    EXPECT_EQ(varyKey({}, {"Accept-Language: fr"}), "");
}
