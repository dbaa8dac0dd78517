"""The learning environments (mimo_ta.gym, docs/decisions/0311-learning-environments.md,
docs/decisions/0316-built-in-tracker-external-resource-manager.md): the frameworks' checkers,
seeded reproducibility, the rule policy against the built-in default test article (byte for byte)
and against the simple test article, the defer action, bad input, and no process left behind. Short episodes of scenario 1 with the mimo binary of the
checkout (target/debug, else target/release, else MIMO_BIN or the installed one); skipped when
gymnasium or a binary is missing."""

import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

import numpy as np

try:
    import gymnasium
    from gymnasium.utils.env_checker import check_env
except ImportError:  # the [gym] extra is not installed
    gymnasium = None

REPO = Path(__file__).resolve().parents[2]


def mimo_bin():
    env = os.environ.get("MIMO_BIN")  # e.g. a release build
    if env:
        return env
    for profile in ("debug", "release"):
        p = REPO / "target" / profile / "mimo"
        if p.is_file() and os.access(p, os.X_OK):
            return str(p)
    return shutil.which("mimo")


MIMO = mimo_bin()
SKIP = gymnasium is None or MIMO is None
WHY = "gymnasium (pip install './python[gym]') or a mimo binary (cargo build --bin mimo) is missing"


def gone(pgid: int) -> bool:
    """No live process (zombies aside: a container's init may not reap them) in the group."""
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[2]) == pgid and fields[0] != "Z":
            return False
    return True


@unittest.skipIf(SKIP, WHY)
class NetworkEnvTest(unittest.TestCase):
    def make(self, **kw):
        from mimo_ta.gym import NetworkEnv

        kw.setdefault("duration_s", 8.0)
        env = NetworkEnv(scenario=1, mimo_bin=MIMO, **kw)
        self.addCleanup(env.close)
        return env

    def test_gymnasium_check_env_passes(self):
        import mimo_ta.gym  # noqa: F401 - registers mimo/Network-v0

        env = gymnasium.make("mimo/Network-v0", duration_s=4.0, mimo_bin=MIMO)
        try:
            check_env(env.unwrapped)  # the raw environment, as check_env recommends
        finally:
            env.close()

    def run_rule(self, env, seed, steps=None):
        from mimo_ta.gym.policies import rule_policy

        obs, info = env.reset(seed=seed)
        out, total = [obs], 0.0
        n = 0
        while steps is None or n < steps:
            obs, r, term, trunc, info = env.step(rule_policy(env, obs))
            self.assertTrue(env.observation_space.contains(obs))
            out.append(obs)
            total += r
            n += 1
            if term:
                break
        return out, total, info

    def test_same_seed_same_episode(self):
        env = self.make()
        a, ra, ia = self.run_rule(env, 7)
        b, rb, ib = self.run_rule(env, 7)
        self.assertEqual(len(a), len(b))
        for x, y in zip(a, b):
            for k in x:
                np.testing.assert_array_equal(x[k], y[k])
        self.assertEqual(ra, rb)
        self.assertEqual(ia["score"]["completeness"], ib["score"]["completeness"])
        c, _, ic = self.run_rule(env, 8)
        self.assertNotEqual([o["tracks"].tobytes() for o in a], [o["tracks"].tobytes() for o in c])
        env = self.make(tracker="simple")
        a, ra, _ = self.run_rule(env, 7)
        b, rb, _ = self.run_rule(env, 7)
        self.assertEqual((len(a), ra), (len(b), rb))

    def test_the_rule_policy_is_the_built_in_default_test_article(self):
        """With the built-in tracker the rule policy defers to the built-in rule: the episode's
        tables are those of `mimo simulate --tracker default`, byte for byte, and the online
        completeness (the reward's) is mimo score's."""
        with tempfile.TemporaryDirectory() as tmp:
            env = self.make(duration_s=15.0, workdir=os.path.join(tmp, "gym"))
            self.assertEqual(env.tracker, "builtin")
            _, total, info = self.run_rule(env, 3)
            s = info["score"]
            self.assertAlmostEqual(s["online_completeness"], s["completeness"], places=9)
            out = os.path.join(tmp, "run")
            subprocess.run([MIMO, "simulate", "--scenario", "1", "--seed", "3", "--duration", "15.0", "--threads", "1",
                            "--quiet", "--out", out, "--tracker", "default"], check=True)
            for table in ("tracks", "dwells", "measurements"):
                a = Path(s["run_dir"], table, "run-0000.parquet").read_bytes()
                b = Path(out, table, "run-0000.parquet").read_bytes()
                self.assertTrue(a == b, f"{table} differs from the built-in default's")
            self.assertAlmostEqual(s["energy_estimate_j"] / s["energy_j"], 1.0, delta=0.02)
            self.assertAlmostEqual(total, s["online_completeness"] - 1e-3 * s["energy_estimate_j"] / 1e3, places=6)

    def test_defer_accepts_the_rules_proposals_but_the_agents_own_look(self):
        """*defer* accepts every proposal of the built-in rule except one at a track the agent
        gave a look at this decision point; a plain wait accepts none."""
        from mimo_ta.gym import Action

        env = self.make(duration_s=30.0)
        env.reset(seed=1)
        run = env.run
        sent = []
        real_send = run._send
        run._send = lambda reply: (sent.append(reply), real_send(reply))[1]

        def point(same: bool):
            """Run (deferring) to a point with a proposal and a track the agent may look at: the
            proposal's own track (`same`) or another one; return (that track's id, its slot)."""
            for _ in range(5000):
                proposed = {tid for p in run.proposed if "dwell" in p for tid in p["dwell"]["tag"]}
                for slot, tid in enumerate(run.slots):
                    if proposed and tid is not None and (tid in proposed) == same and run.visibility(slot) \
                            and run.look_problem(slot, next(iter(run.visibility(slot))), False, 4) is None:
                        return tid, slot
                env.step(env.defer_action)
            self.fail("no such decision point")

        for same in (False, True):
            tid, slot = point(same)
            tx = next(iter(run.visibility(slot)))
            env.step(env.encode(Action("look", slot=slot, transmitter=tx, mimo=False, pulses=4)))
            expected = [i for i, p in enumerate(run.proposed) if "dwell" not in p or tid not in p["dwell"]["tag"]]
            self.assertEqual(bool(expected), not same)
            env.step(env.defer_action)
            reply = sent[-1]
            self.assertEqual(reply.get("accept", []), expected)
            own = [r["dwell"] for r in reply["requests"] if "dwell" in r]
            self.assertEqual([(d["tag"], d["transmitters"]) for d in own], [([tid], [{"radar": tx, "n_pulses": 4}])])
            self.assertNotIn("tracks", reply)
        while not any("dwell" in p for p in run.proposed):
            env.step(env.defer_action)
        env.step(0)  # a wait accepts nothing
        self.assertNotIn("accept", sent[-1])
        with self.assertRaisesRegex(ValueError, "tracker"):
            self.make(tracker="ekf")

    def test_the_rule_policy_is_the_simple_test_article(self):
        """With the simple tracker, the rule through the environment and mimo_ta.simple run by mimo
        give the same score, and the online completeness (the reward's) is mimo score's."""
        env = self.make(duration_s=15.0, tracker="simple")
        _, total, info = self.run_rule(env, 3)
        s = info["score"]
        self.assertAlmostEqual(s["online_completeness"], s["completeness"], places=9)
        with tempfile.TemporaryDirectory() as tmp:
            out = os.path.join(tmp, "run")
            subprocess.run([MIMO, "simulate", "--scenario", "1", "--seed", "3", "--duration", "15.0", "--threads", "1",
                            "--quiet", "--out", out, "--ta-cmd",
                            f"{sys.executable} {REPO / 'python' / 'examples' / 'simple_ta.py'}"], check=True)
            subprocess.run([MIMO, "score", out, "--no-charts", "--quiet", "--threads", "1"], check=True)
            with open(os.path.join(out, "score", "summary.json")) as f:
                ref = json.load(f)
        self.assertEqual(s["completeness"], ref["track"]["completeness"])
        self.assertEqual(s["energy_j"], ref["usage"]["total_energy_j"])
        # The reward: completeness share minus lambda x energy (estimated online, within 2 %).
        self.assertAlmostEqual(s["energy_estimate_j"] / s["energy_j"], 1.0, delta=0.02)
        self.assertAlmostEqual(total, s["online_completeness"] - 1e-3 * s["energy_estimate_j"] / 1e3, places=6)

    def test_bad_actions_name_the_field_and_send_nothing(self):
        from mimo_ta.gym import Action

        env = self.make()
        obs, _ = env.reset(seed=1)
        for bad in (-1, env.action_space.n, 2.5, "3", np.array([1, 2])):
            with self.assertRaisesRegex(ValueError, "outside the action space"):
                env.step(bad)
        while not (obs["tracks"][:, 0] > 0).any():
            obs, *_ = env.step(0)
        run = env.run
        empty = int(np.flatnonzero(obs["tracks"][:, 0] == 0)[0])
        before = (run.steps, len(run.requests), run.now_s)
        with self.assertRaisesRegex(ValueError, "masked: track: slot"):
            env.step(env.encode(Action("look", slot=empty, transmitter="R1", mimo=False, pulses=0)))
        mask = env.action_masks()
        held = int(np.flatnonzero(obs["tracks"][:, 0] > 0)[0])
        masked = [a for a in range(env.n_wait, env.action_space.n) if not mask[a] and env.decode(a).slot == held]
        if masked:
            with self.assertRaisesRegex(ValueError, "masked: (transmitter|receivers|pulses|track)"):
                env.step(masked[0])
        self.assertEqual((run.steps, len(run.requests), run.now_s), before)
        # Every action the mask allows is taken.
        a = int(np.flatnonzero(mask[env.n_wait:])[0]) + env.n_wait
        env.step(a)
        self.assertEqual(len(run.requests), 1)

    def test_an_unloadable_scenario_raises_mimos_error(self):
        from mimo_ta.gym import MimoError, NetworkEnv

        with self.assertRaisesRegex(MimoError, "error: .*cannot read scenario file"):
            NetworkEnv(scenario=Path("/nonexistent/scenario.toml"), mimo_bin=MIMO, duration_s=4.0)
        with self.assertRaisesRegex(MimoError, "unknown standard scenario 99"):
            NetworkEnv(scenario=99, mimo_bin=MIMO, duration_s=4.0)

    def test_closing_mid_episode_leaves_no_process(self):
        env = self.make()
        env.reset(seed=2)
        for _ in range(5):
            env.step(0)
        pgid = env.run.proc.pid
        self.assertFalse(gone(pgid))
        env.close()
        self.assertTrue(gone(pgid))
        env.close()  # twice is fine

    def test_a_crashed_mimo_raises_with_its_stderr_and_leaves_nothing(self):
        from mimo_ta.gym import MimoError

        env = self.make()
        env.reset(seed=2)
        env.step(0)
        pgid = env.run.proc.pid
        os.kill(pgid, signal.SIGKILL)  # mimo itself dies; the relay is left
        with self.assertRaisesRegex(MimoError, "mimo stopped"):
            for _ in range(10000):
                env.step(0)
        self.assertTrue(gone(pgid))

    def test_a_wait_sets_the_search_share(self):
        from mimo_ta.gym import Action

        env = self.make(duration_s=4.0)
        env.reset(seed=1)
        sent = []
        real_send = env.run._send
        env.run._send = lambda reply: (sent.append(reply), real_send(reply))[1]
        obs, *_ = env.step(env.encode(Action("wait", search_share=0.1)))
        orders = [r["search"] for r in sent[0]["requests"] if "search" in r]
        self.assertEqual(sorted(o["radar"] for o in orders), env.radars)
        self.assertTrue(all(o["plan"]["share"] == 0.1 for o in orders))
        np.testing.assert_allclose(obs["radars"][:, 0], 0.1)
        obs, *_ = env.step(env.encode(Action("wait", search_share=0.1)))  # no change, no order
        self.assertFalse(any("search" in r for r in sent[1].get("requests", [])))
        while True:
            *_, term, _, info = env.step(env.encode(Action("wait", search_share=0.0)))
            if term:
                break
        s = info["score"]
        self.assertLess(s["search_energy_j"], 0.2 * 4.0 * sum(env.run.ref.search_rate_j_per_s.values()))

    def test_random_valid_actions_run_to_the_end(self):
        from mimo_ta.gym.policies import random_policy

        env = self.make(duration_s=5.0)
        env.reset(seed=4)
        rng = np.random.default_rng(0)
        term = False
        while not term:
            _, _, term, _, info = env.step(random_policy(env, rng))
        self.assertIn("completeness", info["score"])


if __name__ == "__main__":
    unittest.main()


try:
    import pettingzoo  # noqa: F401
except ImportError:
    pettingzoo = None


@unittest.skipIf(SKIP or pettingzoo is None, WHY + " (or pettingzoo)")
class ParallelNetworkEnvTest(unittest.TestCase):
    def make(self, **kw):
        from mimo_ta.gym import ParallelNetworkEnv

        kw.setdefault("duration_s", 6.0)
        env = ParallelNetworkEnv(scenario=1, mimo_bin=MIMO, **kw)
        self.addCleanup(env.close)
        return env

    def test_pettingzoo_parallel_api_test_passes(self):
        from pettingzoo.test import parallel_api_test

        parallel_api_test(self.make(duration_s=4.0), num_cycles=200)

    def play(self, env, seed):
        obs, _ = env.reset(seed=seed)
        rng = np.random.default_rng(seed)
        trace = []
        while env.agents:
            acts = {a: int(rng.choice(np.flatnonzero(obs[a]["action_mask"]))) for a in env.agents}
            obs, rew, term, _, info = env.step(acts)
            trace.append((acts, rew[env.possible_agents[0]]))
        return trace, info[env.possible_agents[0]]["score"]

    def test_same_seed_same_episode_and_a_shared_reward(self):
        for tracker in ("builtin", "simple"):
            env = self.make(tracker=tracker)
            a, sa = self.play(env, 5)
            b, sb = self.play(env, 5)
            self.assertEqual(a, b)
            self.assertEqual(sa["completeness"], sb["completeness"])

    def test_ships_waiting_accepting_are_the_built_in_default(self):
        with tempfile.TemporaryDirectory() as tmp:
            env = self.make(duration_s=10.0, workdir=os.path.join(tmp, "gym"))
            env.reset(seed=2)
            while env.agents:
                *_, info = env.step({a: env.encode("wait") for a in env.agents})
            run_dir = info[env.possible_agents[0]]["score"]["run_dir"]
            out = os.path.join(tmp, "run")
            subprocess.run([MIMO, "simulate", "--scenario", "1", "--seed", "2", "--duration", "10.0", "--threads", "1",
                            "--quiet", "--out", out], check=True)
            for table in ("tracks", "dwells"):
                self.assertTrue(Path(run_dir, table, "run-0000.parquet").read_bytes()
                                == Path(out, table, "run-0000.parquet").read_bytes(), table)

    def test_mimo_receivers_are_the_ships_that_accept(self):
        env = self.make(duration_s=20.0)
        obs, _ = env.reset(seed=1)
        wait, refuse = env.encode("wait"), env.encode("wait", accept=False)
        for _ in range(5000):
            for slot in range(env.k):
                if env._env.run.track_in(slot) is None:
                    continue
                run = env._env.run
                vis = run.visibility(slot)
                if len(vis) >= 3 and run.look_problem(slot, sorted(vis)[0], True, 1) is None:
                    tx, others = sorted(vis)[0], sorted(vis)[1:]
                    acts = {a: wait for a in env.agents}
                    acts[tx] = env.encode("look", slot=slot, mimo=True, pulses=4)
                    acts[others[0]] = refuse
                    sent = []
                    real_send = run._send
                    run._send = lambda reply: (sent.append(reply), real_send(reply))[1]
                    env.step(acts)
                    dwell = sent[0]["requests"][0]["dwell"]
                    self.assertEqual(dwell["transmitters"], [{"radar": tx, "n_pulses": 4}])
                    self.assertIn(tx, dwell["receivers"])
                    self.assertNotIn(others[0], dwell["receivers"])
                    self.assertGreater(len(dwell["receivers"]), 1)
                    return
            obs, *_ = env.step({a: wait for a in env.agents})
            if not env.agents:
                break
        self.fail("no track seen by three radars")

    def test_a_bad_action_names_the_agent_and_sends_nothing(self):
        env = self.make()
        env.reset(seed=1)
        run = env._env.run
        before = (run.steps, run.now_s)
        acts = {a: env.encode("wait") for a in env.agents}
        acts["R2"] = env.n_actions
        with self.assertRaisesRegex(ValueError, r"actions\['R2'\].*outside the action space"):
            env.step(acts)
        acts["R2"] = env.encode("look", slot=0, mimo=False, pulses=0)
        with self.assertRaisesRegex(ValueError, r"actions\['R2'\].*masked: track"):
            env.step(acts)
        del acts["R2"]
        with self.assertRaisesRegex(ValueError, "no action for agent"):
            env.step(acts)
        self.assertEqual((run.steps, run.now_s), before)


try:
    import stonesoup  # noqa: F401
except ImportError:
    stonesoup = None


@unittest.skipIf(SKIP or stonesoup is None, WHY + " (or Stone Soup)")
class StoneSoupManagerTest(unittest.TestCase):
    def test_a_greedy_manager_chooses_looks_and_the_reward_prices_them(self):
        from stonesoup.sensormanager import GreedySensorManager

        from mimo_ta.gym import NetworkEnv
        from mimo_ta.stonesoup.manager import LookReward, radars_of, run_episode

        env = NetworkEnv(scenario=1, duration_s=8.0, mimo_bin=MIMO)
        self.addCleanup(env.close)
        reward = LookReward(env=env)
        manager = GreedySensorManager(sensors=radars_of(env), reward_function=reward)
        ret, info = run_episode(env, manager, seed=1)
        self.assertGreater(info["score"]["ta_energy_j"], 0.0)  # it looked
        # Same state, dearer energy and time: every look is worth less, no look stays 0.
        env.reset(seed=1)
        while not any(env.run.track_in(s) is not None for s in range(env.k)):
            env.step(0)
        slot = next(s for s in range(env.k) if env.run.track_in(s) is not None)
        tx = next(iter(env.run.visibility(slot)))
        cheap = reward.look_value(tx, slot, False, 4)
        dear = LookReward(env=env, price_per_kj=1e4, price_per_s=1e3).look_value(tx, slot, False, 4)
        self.assertLess(dear, cheap)
        self.assertGreater(reward.look_value(tx, slot, False, 16) + 0.0, -1e9)
        (radar,) = [r for r in radars_of(env) if r.radar == tx]
        gen = next(iter(radar.actions(None)))
        looks = list(gen)
        self.assertIsNone(looks[0].slot)  # no look first
        self.assertIn(slot, {a.slot for a in looks})
        self.assertEqual(reward({radar: (looks[0],)}), 0.0)
