"""The run and study files shipped with evoplan, installed as ``evoplan.examples`` (see ``evoplan examples``)."""
