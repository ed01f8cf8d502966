"""Settings of the ``deap_easimple`` adapter, importable without DEAP (an extra: ``evoplan[deap]``)."""

from __future__ import annotations

from typing import Literal

from pydantic import AliasChoices, Field, model_validator

from .base import AdapterConfig


class DeapEaSimpleConfig(AdapterConfig):
    name: Literal["deap_easimple"] = "deap_easimple"
    representation: Literal["real", "binary"] = "binary"
    population: int = Field(20, ge=2, validation_alias=AliasChoices("population", "pop_size"),
                            description="population size (pymoo's name pop_size is accepted too)")
    cxpb: float = Field(0.5, ge=0, le=1, description="probability of mating a pair (DEAP examples: 0.5)")
    mutpb: float = Field(0.2, ge=0, le=1, description="probability of mutating an individual (0.2)")
    tournament: int = Field(3, ge=1, description="selTournament size")
    crossover: Literal["one_point", "two_point"] = Field("two_point", description="binary: cxOnePoint / cxTwoPoint")
    indpb: float | None = Field(None, gt=0, le=1, description="per-gene mutation probability; None: 1 / length")
    eta_crossover: float = Field(15.0, gt=0, description="real: cxSimulatedBinaryBounded eta")
    eta_mutation: float = Field(20.0, gt=0, description="real: mutPolynomialBounded eta")

    @model_validator(mode="before")
    @classmethod
    def _one_population(cls, data):
        if isinstance(data, dict) and "population" in data and "pop_size" in data:
            if data["population"] != data["pop_size"]:
                raise ValueError(f"population {data['population']} and pop_size {data['pop_size']} differ: "
                                 "they are one setting, give one of them")
            data = {k: v for k, v in data.items() if k != "pop_size"}
        return data

    @model_validator(mode="after")
    def _something_varies(self):
        if self.cxpb == 0 and self.mutpb == 0:
            raise ValueError("cxpb and mutpb are both 0: no individual would ever change")
        return self
