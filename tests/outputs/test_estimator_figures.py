"""Figures 2.1 and 2.2: the estimators' table from a walk's scores, each estimator under the thesis's name."""

from mjx_badger.outputs import estimator_figures


def test_the_table_names_each_estimator_and_gives_its_ratio_errors_and_drift():
    scores = {"kinematic-kalman": {"ratio_to_truth": 0.015, "mae_vx": 0.41, "mae_vy": 0.05, "drift_vx": -0.002}}
    report = {"seconds": 20.0, "walks": {"jt-oef crossq": {"true_mean_vx": 0.42, "falls": 0, "scores": scores}},
              "fit": {"thesis": {"final_train_mae": 0.19, "final_validation_mae": 0.21, "best_validation_mae": 0.2}}}
    table = estimator_figures.table(report)
    assert table.startswith("Over 20 s on native MuJoCo with sensor noise:")
    assert ("| jt-oef crossq (true mean vx 0.42 m/s, 0 falls) | (a) kinematics + IMU, all four feet (the thesis's robot) "
            "| 0.01 | 0.410 | 0.050 | -0.002 |") in table
    assert "| thesis | 0.190 | 0.210 | 0.200 | saturates at 0.2; adequate below 0.05 |" in table
