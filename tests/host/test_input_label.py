"""The HUD and the status line say where the data comes from and at what rate."""
from backends.oscin.backend import OscInBackend, OscInOptions
from backends.truth import TruthBackend
from host.metrics import Metrics, input_of
from host.render.hud import lines
from host.status import line, summary
from sources.synthetic import SyntheticSource


def test_a_source_backed_backend_names_its_source_and_rate():
    metrics = Metrics("truth", 30.0, input=input_of(TruthBackend(SyntheticSource())))
    assert metrics.input_label == "source synthetic 30 Hz"
    assert "truth[/] <- source synthetic 30 Hz" in line(metrics)
    assert lines(metrics)[:2] == ["backend truth", "input source synthetic 30 Hz"]


def test_osc_in_names_scheme_port_users_and_message_rate():
    backend = OscInBackend(None, OscInOptions(port=0, scheme="synapse", synapse_port=9), warn=lambda _: None)
    metrics = Metrics("osc-in", 0.0, input=input_of(backend))
    assert metrics.input_label == "osc synapse (not listening yet)"
    with backend:
        assert metrics.input_label == f"osc synapse :{backend.port}, 0 users, 0 msg/s"


def test_the_summary_names_the_input_and_no_source_rate_without_a_source(capsys):
    backend = OscInBackend(None, OscInOptions(port=0, scheme="osceleton"), warn=lambda _: None)
    summary(Metrics("osc-in", 0.0, input=input_of(backend)))
    out = capsys.readouterr().err
    assert "osc osceleton (not listening yet)" in out and "source rate" not in out
    summary(Metrics("truth", 30.0, input=input_of(TruthBackend(SyntheticSource()))))
    out = capsys.readouterr().err
    assert "source synthetic 30 Hz" in out and "30.00 Hz" in out
