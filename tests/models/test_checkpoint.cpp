// tests/models/test_checkpoint.cpp: the checkpoint format of the models layer
// (varsym/models/checkpoint.hpp): a simulation saved into a checkpoint's text, read back and
// restored into a new simulation continues bit for bit (the reference: the run that never
// stopped); a damaged or foreign text is refused with a message that says why.
#include <gtest/gtest.h>

#include <string>

#include "varsym/models/checkpoint.hpp"
#include "varsym/models/model.hpp"

namespace vm = varsym::models;

namespace {

std::unique_ptr<vm::simulation> kepler() {
    const vm::model& m = vm::get("kepler");
    const vm::problem pr = m.prepare(m.defaults());
    // The simplified iteration keeps a history (its Jacobian's point): the text must carry it.
    varsym::newton_options newton;
    newton.iteration = varsym::iteration_kind::simplified;
    return pr.simulate(
        {varsym::scheme_spec(varsym::scheme_kind::gauss, 3), newton, pr.period / 100.0});
}

} // namespace

TEST(Checkpoint, ASavedSimulationContinuesBitForBitThroughItsText) {
    const auto straight = kepler();
    straight->advance(250);
    const auto first = kepler();
    first->advance(97);
    vm::checkpoint ck;
    ck.args = {"run", "--model", "kepler", "an argument\nwith a newline and a \\"};
    ck.output = "/tmp/out.csv";
    ck.scheme = "gauss-3";
    ck.steps = 250;
    ck.h = first->step_size();
    ck.set_state(first->save());
    const vm::checkpoint back = vm::parse_checkpoint(vm::checkpoint_text(ck), "test");
    EXPECT_EQ(back.args, ck.args);
    EXPECT_EQ(back.output, ck.output);
    EXPECT_EQ(back.h, ck.h); // hexadecimal floats: exact
    EXPECT_EQ(back.step, 97U);
    EXPECT_FALSE(back.history.empty());
    const auto second = kepler();
    second->restore(back.state());
    second->advance(250);
    for (std::size_t i = 0; i < 2; ++i) {
        EXPECT_EQ(second->q()[i], straight->q()[i]);
        EXPECT_EQ(second->p()[i], straight->p()[i]);
    }
    EXPECT_EQ(second->stats().newton_iterations, straight->stats().newton_iterations);
}

TEST(Checkpoint, RefusesDamagedForeignAndOtherVersionsTexts) {
    vm::checkpoint ck;
    ck.scheme = "simpson";
    ck.steps = 10;
    ck.h = 0.1;
    ck.q = ck.p = ck.carry_q = ck.carry_p = {1.0};
    const std::string text = vm::checkpoint_text(ck);
    EXPECT_NO_THROW((void)vm::parse_checkpoint(text, "ok")); // the control: the intact text
    auto refused = [](const std::string& t, const std::string& why) {
        try {
            (void)vm::parse_checkpoint(t, "ck");
            ADD_FAILURE() << "accepted: " << why;
        } catch (const vm::checkpoint_error& e) {
            EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
        }
    };
    std::string flipped = text;
    flipped[flipped.find("steps 10") + 7] = '9'; // one digit changed: the CRC-32 sees it
    refused(flipped, "CRC-32 checksum mismatch");
    refused(text.substr(0, text.size() - 5), "truncated");
    refused("hello\n", "is not a varsym checkpoint");
    std::string other = text;
    other.replace(other.find(vm::checkpoint_version), std::string(vm::checkpoint_version).size(),
                  "0.0.1");
    refused(other, "was written by varsym 0.0.1");
    EXPECT_TRUE(vm::looks_like_checkpoint_start(text.substr(0, 7))); // a write cut short
    EXPECT_TRUE(vm::looks_like_checkpoint_start(""));
    EXPECT_FALSE(vm::looks_like_checkpoint_start("step,t,q,p"));
}
