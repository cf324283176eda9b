// bench/interleaved.hpp: runs benchmark cases in interleaved rounds (every case once per round,
// in turn, so that a noisy neighbour on a shared machine slows them all alike) and keeps each
// case's run with the median time. For the standalone benchmark programs (bench_optimal.cpp,
// bench_robot_optimal.cpp), whose outcomes have a `seconds` field.
#pragma once

#include <algorithm>
#include <functional>
#include <vector>

namespace varsym::bench {

template <class Outcome>
std::vector<Outcome> interleaved(const std::vector<std::function<Outcome()>>& cases, int rounds) {
    std::vector<std::vector<Outcome>> all(cases.size());
    for (int r = 0; r < rounds; ++r)
        for (std::size_t c = 0; c < cases.size(); ++c)
            all[c].push_back(cases[c]());
    std::vector<Outcome> out;
    for (auto& runs : all) {
        std::sort(runs.begin(), runs.end(),
                  [](const Outcome& a, const Outcome& b) { return a.seconds < b.seconds; });
        out.push_back(runs[runs.size() / 2]);
    }
    return out;
}

} // namespace varsym::bench
